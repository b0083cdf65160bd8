//! Where each patch block's points live in a frame's vertex buffer ([`Slots`]).
//!
//! A recomputed block is written back into its own slot while it fits there, else into a new
//! slot at the end of the buffer; once the slots left behind hold more points than the live
//! blocks, the buffer is laid out afresh, block after block. A frame that recomputes a few
//! blocks therefore rewrites only their points, and every other vertex keeps its index and its
//! bits: a renderer that keeps the buffer uploads only the rewritten ranges
//! ([`AdaptiveFrame::dirty_vertices`](crate::AdaptiveFrame::dirty_vertices)).

use std::ops::Range;

use subdiv_rules::budget::try_reserve;
use subdiv_rules::{OutOfMemory, TriangleBuffers};

/// The blocks' slots in a vertex buffer.
#[derive(Clone, Debug, Default)]
pub(crate) struct Slots {
    /// Per block: first vertex of its slot.
    start: Vec<u32>,
    /// Per block: points it holds now (from `start`).
    len: Vec<u32>,
    /// Per block: points its slot has room for.
    cap: Vec<u32>,
    /// Vertices of the buffer (slots, live or left behind).
    end: u32,
}

impl Slots {
    /// Slots for `n` blocks, none placed yet.
    pub(crate) fn new(n: usize) -> Slots {
        Slots {
            start: vec![0; n],
            len: vec![0; n],
            cap: vec![0; n],
            end: 0,
        }
    }

    /// First vertex of block `i`.
    #[inline(always)]
    pub(crate) fn start(&self, i: usize) -> u32 {
        self.start[i]
    }

    /// The vertices of block `i`.
    #[inline]
    pub(crate) fn range(&self, i: usize) -> Range<usize> {
        self.start[i] as usize..(self.start[i] + self.len[i]) as usize
    }

    /// Whether block `i` holds points in the buffer.
    #[inline]
    pub(crate) fn holds(&self, i: usize) -> bool {
        self.len[i] > 0
    }

    /// The vertex buffer of the last write with `block(i)` in place of each block's points:
    /// every slot holding points gets as many of `block(i)` (which has at least that many),
    /// the slots left behind zeros.
    pub(crate) fn gather<'a>(&self, block: impl Fn(usize) -> &'a [[f32; 3]]) -> Vec<[f32; 3]> {
        let mut out = vec![[0.0; 3]; self.end as usize];
        for i in (0..self.start.len()).filter(|&i| self.holds(i)) {
            let r = self.range(i);
            let n = r.len();
            out[r].copy_from_slice(&block(i)[..n]);
        }
        out
    }

    /// The block holding vertex `v`, and `v`'s index in it.
    pub(crate) fn block_of(&self, v: u32) -> Option<(usize, u32)> {
        (0..self.start.len())
            .find(|&i| (self.start[i]..self.start[i] + self.len[i]).contains(&v))
            .map(|i| (i, v - self.start[i]))
    }

    /// Writes into `b`'s vertex buffer the blocks `changed` (ascending; `block(i)` gives block
    /// `i`'s positions and normals), each into its slot if it fits there, else into a new one
    /// at the end; every block, laid out afresh, when `b` does not hold this buffer (its length
    /// differs, as for a new surface) or when the slots left behind would outnumber the live
    /// points. `dirty` receives the vertex ranges written (cleared first, ascending when laid
    /// out afresh, in `changed` order otherwise).
    pub(crate) fn write<'a>(
        &mut self,
        b: &mut TriangleBuffers<'_>,
        block: impl Fn(usize) -> (&'a [[f32; 3]], &'a [[f32; 3]]),
        changed: &[usize],
        dirty: &mut Vec<Range<u32>>,
    ) -> Result<(), OutOfMemory> {
        dirty.clear();
        let size = |i: usize| block(i).0.len() as u32;
        let mut grown = 0u64;
        for &i in changed {
            if size(i) > self.cap[i] {
                grown += u64::from(size(i));
            }
        }
        let mut live: u64 = self.len.iter().map(|&l| u64::from(l)).sum();
        for &i in changed {
            live = live - u64::from(self.len[i]) + u64::from(size(i));
        }
        let kept = self.end > 0
            && b.positions.len() == self.end as usize
            && b.normals.len() == self.end as usize;
        let end = u64::from(self.end) + grown;
        if !kept || end > 2 * live.max(1) || end > u64::from(u32::MAX) {
            return self.lay_out(b, &block, dirty);
        }
        if grown > 0 {
            try_reserve(b.positions, grown as usize, "frame positions")?;
            try_reserve(b.normals, grown as usize, "frame normals")?;
        }
        for &i in changed {
            let (pos, nrm) = block(i);
            let s = pos.len() as u32;
            if s > self.cap[i] {
                self.start[i] = self.end;
                self.cap[i] = s;
                self.end += s;
                b.positions.extend_from_slice(pos);
                b.normals.extend_from_slice(nrm);
            } else {
                let at = self.start[i] as usize;
                b.positions[at..at + pos.len()].copy_from_slice(pos);
                b.normals[at..at + nrm.len()].copy_from_slice(nrm);
            }
            self.len[i] = s;
            dirty.push(self.start[i]..self.start[i] + s);
        }
        Ok(())
    }

    /// Every block, one after the other from vertex 0, each slot its block's size.
    fn lay_out<'a>(
        &mut self,
        b: &mut TriangleBuffers<'_>,
        block: &impl Fn(usize) -> (&'a [[f32; 3]], &'a [[f32; 3]]),
        dirty: &mut Vec<Range<u32>>,
    ) -> Result<(), OutOfMemory> {
        let mut acc = 0u32;
        for i in 0..self.start.len() {
            let s = block(i).0.len() as u32;
            (self.start[i], self.len[i], self.cap[i]) = (acc, s, s);
            acc += s;
        }
        self.end = acc;
        b.positions.clear();
        b.normals.clear();
        try_reserve(b.positions, acc as usize, "frame positions")?;
        try_reserve(b.normals, acc as usize, "frame normals")?;
        for i in 0..self.start.len() {
            let (pos, nrm) = block(i);
            b.positions.extend_from_slice(pos);
            b.normals.extend_from_slice(nrm);
        }
        dirty.push(0..acc);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertex buffer as a surface keeps it.
    #[derive(Default)]
    struct Buffers {
        positions: Vec<[f32; 3]>,
        normals: Vec<[f32; 3]>,
        triangles: Vec<u32>,
        corner_normals: Vec<(u32, [f32; 3])>,
        uvs: Vec<[f32; 2]>,
        uv_indices: Vec<u32>,
        scalar: Vec<f32>,
    }

    impl Buffers {
        fn write(
            &mut self,
            slots: &mut Slots,
            blocks: &[Vec<[f32; 3]>],
            changed: &[usize],
        ) -> Vec<Range<u32>> {
            let mut dirty = Vec::new();
            let mut b = TriangleBuffers {
                positions: &mut self.positions,
                normals: &mut self.normals,
                triangles: &mut self.triangles,
                corner_normals: &mut self.corner_normals,
                uvs: &mut self.uvs,
                uv_indices: &mut self.uv_indices,
                scalar: &mut self.scalar,
            };
            let block = |i: usize| (&blocks[i][..], &blocks[i][..]);
            slots.write(&mut b, block, changed, &mut dirty).unwrap();
            dirty
        }
    }

    fn block(tag: f32, n: usize) -> Vec<[f32; 3]> {
        (0..n).map(|k| [tag, k as f32, 0.0]).collect()
    }

    /// Every block's points are where its slot says.
    fn check(slots: &Slots, buf: &Buffers, blocks: &[Vec<[f32; 3]>]) {
        for (i, b) in blocks.iter().enumerate() {
            assert_eq!(&buf.positions[slots.range(i)], &b[..], "block {i}");
            assert_eq!(&buf.normals[slots.range(i)], &b[..], "block {i}");
        }
    }

    #[test]
    fn blocks_stay_put_while_they_fit_and_move_to_the_end_when_they_grow() {
        let mut blocks = vec![block(0.0, 4), block(1.0, 9), block(2.0, 4)];
        let (mut slots, mut buf) = (Slots::new(3), Buffers::default());
        // A new surface: laid out afresh, all dirty.
        assert_eq!(buf.write(&mut slots, &blocks, &[0, 1, 2]), vec![0..17]);
        check(&slots, &buf, &blocks);
        // Block 1 shrinks: rewritten in its slot, nothing else moves.
        blocks[1] = block(1.5, 4);
        assert_eq!(buf.write(&mut slots, &blocks, &[1]), vec![4..8]);
        check(&slots, &buf, &blocks);
        assert_eq!(buf.positions.len(), 17);
        // Block 0 grows beyond its slot: a new slot at the end.
        blocks[0] = block(0.5, 9);
        assert_eq!(buf.write(&mut slots, &blocks, &[0]), vec![17..26]);
        check(&slots, &buf, &blocks);
        assert_eq!(slots.block_of(20), Some((0, 3)));
        assert_eq!(slots.block_of(5), Some((1, 1)));
        assert_eq!(slots.block_of(1), None, "a slot left behind");
    }

    #[test]
    fn a_buffer_mostly_left_behind_is_laid_out_afresh() {
        let mut blocks = vec![block(0.0, 2), block(1.0, 2)];
        let (mut slots, mut buf) = (Slots::new(2), Buffers::default());
        buf.write(&mut slots, &blocks, &[0, 1]);
        for round in 0..6 {
            blocks[0] = block(round as f32, 3 + round);
            let dirty = buf.write(&mut slots, &blocks, &[0]);
            check(&slots, &buf, &blocks);
            let live = 3 + round + 2;
            assert!(buf.positions.len() <= 2 * live, "round {round}: {dirty:?}");
        }
        // A buffer the slots do not describe (another surface's) is laid out afresh.
        buf.positions.push([9.0; 3]);
        buf.normals.push([9.0; 3]);
        let dirty = buf.write(&mut slots, &blocks, &[1]);
        assert_eq!(dirty, vec![0..(blocks[0].len() + 2) as u32]);
        check(&slots, &buf, &blocks);
    }
}
