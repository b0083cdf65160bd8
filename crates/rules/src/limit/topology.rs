//! Which layout a [`LimitMesh`]'s faces were written for, so that a tessellator called again
//! with the same layout (the per-frame steady state: the cage's positions move, its topology
//! does not) leaves the faces as they are ([`LimitMesh::write_keyed`]), and a renderer knows
//! when to upload them again ([`LimitMesh::topology_written`]).

use std::num::NonZeroU64;
use std::sync::atomic::{AtomicU64, Ordering};

#[cfg(doc)]
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
/// were not written by a keyed tessellator, or changed since) and whether the last
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

impl TopologyStamp {
    /// The faces of the layout `key`, written by this tessellation (`written`) or kept from
    /// the previous one.
    pub(super) fn new(key: TopologyKey, written: bool) -> TopologyStamp {
        TopologyStamp {
            key: Some(key),
            kept: !written,
        }
    }

    /// The layout the faces were written for.
    pub(super) fn key(&self) -> Option<TopologyKey> {
        self.key
    }

    /// Marks keyed faces as kept by the last frame (unkeyed faces stay written).
    pub(super) fn keep(&mut self) {
        self.kept = self.key.is_some();
    }

    /// Whether the last tessellation wrote the faces (`true` for unkeyed faces).
    pub(super) fn written(&self) -> bool {
        !self.kept
    }
}

/// A later frame of the same layout: its points rewritten in place, its faces kept.
impl super::LimitMesh {
    /// The positions and normals together, to rewrite a frame's points in place (the counts
    /// stay; faces, corner normals and UVs are left as they are).
    #[inline]
    pub fn points_and_normals_mut(&mut self) -> (&mut [[f32; 3]], &mut [[f32; 3]]) {
        (&mut self.positions, &mut self.normals)
    }

    /// Records that the last frame rewrote only points and normals of a surface whose faces a
    /// keyed tessellator wrote: [`LimitMesh::topology_written`] is then `false` (a renderer
    /// keeps its index buffer). Nothing changes for faces written without a layout key.
    pub fn keep_faces(&mut self) {
        self.topology.keep();
    }
}

#[cfg(test)]
mod tests {
    use super::super::LimitMesh;
    use super::*;

    #[test]
    fn keys_are_unique_and_stamps_are_not_content() {
        let (a, b) = (TopologyKey::fresh(), TopologyKey::fresh());
        assert_ne!(a, b);
        let mut m = LimitMesh::default();
        assert!(m.topology_written());
        // Writes the faces for `key` and `faces` triangles if not kept; whether it wrote them.
        let write = |m: &mut LimitMesh, key, faces: usize| {
            let w = m.write_keyed(key, 3, faces, 3).unwrap();
            let wrote = w.faces.is_some();
            if let Some(f) = w.faces {
                f.fill(0);
            }
            assert_eq!(m.topology_written(), wrote);
            wrote
        };
        assert!(write(&mut m, a, 1), "first");
        assert!(!write(&mut m, a, 1), "kept");
        assert!(write(&mut m, b, 1), "another key");
        assert!(write(&mut m, a, 1) && write(&mut m, a, 2), "other sizes");
        assert!(write(&mut m, a, 1));
        // Equal content, different stamps: equal meshes; a clone has no key.
        let mut c = m.clone();
        assert_eq!(c, m);
        assert!(c.topology_written() && write(&mut c, a, 1));
        // Removing the faces forgets the layout.
        m.clear_faces();
        assert!(m.topology_written() && m.num_faces() == 0);
        assert!(write(&mut m, a, 1));
    }
}
