//! Which vertices a frame in flight must write: the viewer's slots each hold the vertices of
//! the version they last drew, a frame or two behind, so a slot is brought up to date by the
//! union of the dirty ranges of every version since (as the headless renderer's versioned
//! renders are by one version's).

use std::collections::VecDeque;
use std::ops::Range;

use crate::scene::covers;

/// Versions whose dirty ranges are kept: enough for a slot that missed every frame in flight.
const KEPT: usize = 4;

/// What a slot writes of the vertices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Write {
    /// Every vertex.
    All,
    /// Only these ranges (none when the slot holds this version).
    Ranges(Vec<Range<u32>>),
}

/// The dirty ranges of the last few vertex versions a source reported.
#[derive(Default)]
pub(super) struct History {
    recent: VecDeque<(u64, Option<Vec<Range<u32>>>)>,
}

impl History {
    /// Notes frame `version`'s dirty ranges (against `version - 1`; `None`: not known). A
    /// version seen before keeps what was first noted for it.
    pub(super) fn record(&mut self, version: Option<u64>, dirty: Option<&[Range<u32>]>) {
        let Some(v) = version else {
            return;
        };
        if self.recent.iter().any(|&(w, _)| w == v) {
            return;
        }
        if self.recent.len() == KEPT {
            self.recent.pop_front();
        }
        self.recent.push_back((v, dirty.map(<[_]>::to_vec)));
    }

    /// What a slot holding `held` (version and vertex count) writes for version `version` of
    /// `n` vertices: only the ranges dirtied since its version, when every version since is
    /// known and they cover any vertices appended since; everything otherwise.
    pub(super) fn write(
        &self,
        held: Option<(u64, usize)>,
        version: Option<u64>,
        n: usize,
    ) -> Write {
        let (Some((from, count)), Some(to)) = (held, version) else {
            return Write::All;
        };
        if from > to || (from == to && count != n) {
            return Write::All;
        }
        let mut ranges = Vec::new();
        for v in from + 1..=to {
            match self.recent.iter().find(|&&(w, _)| w == v) {
                Some((_, Some(dirty))) => ranges.extend(dirty.iter().cloned()),
                _ => return Write::All,
            }
        }
        if n > count && !covers(&ranges, count as u32..n as u32) {
            return Write::All;
        }
        Write::Ranges(ranges)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[allow(clippy::single_range_in_vec_init)]
    #[test]
    fn a_slot_writes_the_ranges_of_every_version_since_its_own() {
        let mut h = History::default();
        h.record(Some(5), Some(&[0..10]));
        h.record(Some(6), Some(&[20..30]));
        h.record(Some(6), Some(&[0..100]));
        h.record(Some(7), Some(&[40..50, 100..120]));
        // Two versions behind, grown from 100 to 120 vertices: 6's and 7's ranges.
        assert_eq!(
            h.write(Some((5, 100)), Some(7), 120),
            Write::Ranges(vec![20..30, 40..50, 100..120])
        );
        // The same version: nothing to write; another vertex count: everything.
        assert_eq!(h.write(Some((7, 120)), Some(7), 120), Write::Ranges(vec![]));
        assert_eq!(h.write(Some((7, 120)), Some(7), 121), Write::All);
        // Appended vertices not among the dirty ones, a version not known, no version, a
        // slot ahead of the source, an empty slot: everything.
        assert_eq!(h.write(Some((6, 90)), Some(7), 120), Write::All);
        assert_eq!(h.write(Some((3, 100)), Some(7), 120), Write::All);
        assert_eq!(h.write(Some((5, 100)), None, 120), Write::All);
        assert_eq!(h.write(Some((8, 120)), Some(7), 120), Write::All);
        assert_eq!(h.write(None, Some(7), 120), Write::All);
        // A version whose ranges were not reported.
        h.record(Some(8), None);
        assert_eq!(h.write(Some((7, 120)), Some(8), 120), Write::All);
        // Only the last few versions are kept.
        for v in 9..20 {
            h.record(Some(v), Some(&[]));
        }
        assert_eq!(h.write(Some((9, 120)), Some(19), 120), Write::All);
        assert_eq!(
            h.write(Some((16, 120)), Some(19), 120),
            Write::Ranges(vec![])
        );
    }
}
