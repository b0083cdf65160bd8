//! Green families: which triangles are green closures, and of which parent.

use subdiv_mesh::{FaceId, VertexId};

/// `family_of_face` value of a face that is not green.
pub const NO_FAMILY: u32 = u32::MAX;

/// The triangles of one green closure: the parent triangle they replace and the midpoints of its
/// split edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GreenFamily {
    /// The parent triangle's corners, counter-clockwise.
    pub parent: [VertexId; 3],
    /// `mids[k]` is the vertex on edge `parent[k]`-`parent[k+1]`, or [`VertexId::NONE`] when
    /// that edge is not split.
    pub mids: [VertexId; 3],
}

impl GreenFamily {
    /// Number of split parent edges (1 or 2 for a green family).
    #[inline]
    pub fn num_splits(&self) -> usize {
        self.mids.iter().filter(|m| m.is_some()).count()
    }
}

/// Which faces of a mesh are green, and their families.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GreenState {
    /// Per face: index into [`GreenState::families`], or [`NO_FAMILY`].
    pub family_of_face: Vec<u32>,
    /// The green families.
    pub families: Vec<GreenFamily>,
}

impl GreenState {
    /// No green faces in a mesh of `num_faces` faces (a cage, or a uniformly refined mesh).
    pub fn new(num_faces: usize) -> GreenState {
        GreenState {
            family_of_face: vec![NO_FAMILY; num_faces],
            families: Vec::new(),
        }
    }

    /// The family of face `f`, if it is green.
    #[inline]
    pub fn family(&self, f: FaceId) -> Option<&GreenFamily> {
        self.families
            .get(*self.family_of_face.get(f.idx())? as usize)
    }

    /// Number of green faces.
    pub fn num_green_faces(&self) -> usize {
        self.family_of_face
            .iter()
            .filter(|&&x| x != NO_FAMILY)
            .count()
    }
}
