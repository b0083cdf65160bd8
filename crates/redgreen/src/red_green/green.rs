//! Green families: which triangles are green closures, and of which parent.

use subdiv_mesh::{FaceId, VertexId};

use crate::RedGreenError;

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

/// The faces of every green family, grouped by a counting sort ([`GreenState::family_faces`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct FamilyFaces {
    start: Vec<u32>,
    faces: Vec<u32>,
}

impl FamilyFaces {
    /// The faces of family `fam`, in face order.
    #[inline]
    pub(crate) fn of(&self, fam: u32) -> &[u32] {
        let k = fam as usize;
        &self.faces[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

impl GreenState {
    /// The faces of every family; a face naming a family that does not exist is an error.
    pub(crate) fn family_faces(&self) -> Result<FamilyFaces, RedGreenError> {
        let nfam = self.families.len();
        let mut start = vec![0u32; nfam + 1];
        for (f, &fam) in self.family_of_face.iter().enumerate() {
            if fam != NO_FAMILY {
                if fam as usize >= nfam {
                    return Err(RedGreenError::FamilyOutOfRange {
                        face: f as u32,
                        family: fam,
                        count: nfam as u32,
                    });
                }
                start[fam as usize + 1] += 1;
            }
        }
        for k in 0..nfam {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut faces = vec![0u32; start[nfam] as usize];
        for (f, &fam) in self.family_of_face.iter().enumerate() {
            if fam != NO_FAMILY {
                faces[fill[fam as usize] as usize] = f as u32;
                fill[fam as usize] += 1;
            }
        }
        Ok(FamilyFaces { start, faces })
    }
}
