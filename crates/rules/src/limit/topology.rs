//! Which layout a [`LimitMesh`]'s faces were written for, so that a tessellator called again
//! with the same layout (the per-frame steady state: the cage's positions move, its topology
//! does not) leaves `face_offsets` and `face_indices` as they are, and a renderer knows when to
//! upload them again.

use std::num::NonZeroU64;
use std::sync::atomic::{AtomicU64, Ordering};

use super::LimitMesh;

/// The identity of a tessellation layout whose faces are a function of the layout alone (a
/// slate `PatchLayout` or `TriLayout`): unique in the process, never reused, a new one for
/// every layout built (and every clone made).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TopologyKey(NonZeroU64);

impl TopologyKey {
    /// A key no layout of this process has had.
    pub fn fresh() -> TopologyKey {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        let k = NEXT.fetch_add(1, Ordering::Relaxed);
        // 2^64 layouts are never built; the counter cannot wrap back to 0.
        TopologyKey(NonZeroU64::new(k).unwrap_or(NonZeroU64::MIN))
    }
}

/// Bookkeeping of a [`LimitMesh`]'s faces: the layout they were written for (none when they
/// were not written by a keyed tessellator, or were invalidated) and whether the last
/// tessellation into the mesh wrote them. Not content: [`LimitMesh`]'s equality ignores it.
/// A clone starts without a key (the next keyed tessellation into it writes its faces).
#[derive(Debug, Default)]
pub struct TopologyStamp {
    key: Option<TopologyKey>,
    kept: bool,
}

impl Clone for TopologyStamp {
    fn clone(&self) -> TopologyStamp {
        TopologyStamp::default()
    }
}

impl LimitMesh {
    /// Whether the last tessellation into this mesh wrote `face_offsets` and `face_indices`
    /// (`true` for a mesh not written by a keyed tessellator): a renderer uploads its index
    /// buffer again when this is `true` and may keep the one it has otherwise.
    pub fn topology_written(&self) -> bool {
        !self.topology.kept
    }

    /// Forgets which layout the faces were written for, so that the next tessellation into
    /// this mesh writes them. Call it after changing `face_offsets` or `face_indices` by hand
    /// (a keyed tessellator with the same layout would otherwise keep the changed values).
    pub fn invalidate_topology(&mut self) {
        self.topology = TopologyStamp::default();
    }

    /// For tessellators: whether the faces were written for `key` and still number `faces`
    /// faces with `corners` corners in all (then they are what the layout of `key` writes,
    /// unless changed by hand without [`LimitMesh::invalidate_topology`]).
    pub fn has_topology(&self, key: TopologyKey, faces: usize, corners: usize) -> bool {
        self.topology.key == Some(key)
            && self.face_offsets.len() == faces + 1
            && self.face_indices.len() == corners
    }

    /// For tessellators: records that the faces are those of `key`, and whether this
    /// tessellation wrote them (`written`) or kept them ([`LimitMesh::has_topology`]).
    pub fn set_topology(&mut self, key: TopologyKey, written: bool) {
        self.topology = TopologyStamp {
            key: Some(key),
            kept: !written,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_unique_and_stamps_are_not_content() {
        let (a, b) = (TopologyKey::fresh(), TopologyKey::fresh());
        assert_ne!(a, b);
        let mut m = LimitMesh {
            face_offsets: vec![0, 3],
            face_indices: vec![0, 1, 2],
            ..LimitMesh::default()
        };
        assert!(m.topology_written() && !m.has_topology(a, 1, 3));
        m.set_topology(a, false);
        assert!(!m.topology_written());
        assert!(m.has_topology(a, 1, 3));
        assert!(!m.has_topology(b, 1, 3), "another key");
        assert!(
            !m.has_topology(a, 2, 3) && !m.has_topology(a, 1, 4),
            "other sizes"
        );
        // Equal content, different stamps: equal meshes; a clone has no key.
        let c = m.clone();
        assert_eq!(c, m);
        assert!(!c.has_topology(a, 1, 3) && c.topology_written());
        m.face_indices.pop();
        assert!(!m.has_topology(a, 1, 3), "a shorter index list");
        m.face_indices.push(2);
        m.invalidate_topology();
        assert!(!m.has_topology(a, 1, 3) && m.topology_written());
    }
}
