//! A polygon soup: the unvalidated input from which a [`Mesh`](crate::Mesh) is built.

use glam::Vec3;

use crate::options::SchemeOptions;

/// A crease tag: the edge `a`-`b` gets `sharpness` (>= 10 is infinitely sharp).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreaseTag {
    /// Endpoint (0-based vertex index).
    pub a: i64,
    /// Endpoint (0-based vertex index).
    pub b: i64,
    /// Sharpness.
    pub sharpness: f32,
    /// 1-based source line, if any.
    pub line: Option<u32>,
}

/// A corner tag: vertex `v` gets `sharpness`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerTag {
    /// Vertex (0-based).
    pub v: i64,
    /// Sharpness.
    pub sharpness: f32,
    /// 1-based source line, if any.
    pub line: Option<u32>,
}

/// A hole tag: face `f` is a hole (kept in the topology, never output).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoleTag {
    /// Face (0-based, in input order).
    pub f: i64,
    /// 1-based source line, if any.
    pub line: Option<u32>,
}

/// Positions, faces and tags as read from a file or made in code.
///
/// Faces are stored compressed: face `i` uses `face_indices[face_offsets[i]..face_offsets[i+1]]`.
/// Indices are signed so that out-of-range input (e.g. a negative OBJ index that resolves below
/// zero) survives until validation reports it.
#[derive(Clone, Debug, Default)]
pub struct PolygonSoup {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Start of each face in `face_indices`, plus a final end offset (empty soups may leave it empty).
    pub face_offsets: Vec<u32>,
    /// Vertex indices of all faces, 0-based.
    pub face_indices: Vec<i64>,
    /// Edge sharpness tags.
    pub creases: Vec<CreaseTag>,
    /// Vertex sharpness tags.
    pub corners: Vec<CornerTag>,
    /// Hole tags.
    pub holes: Vec<HoleTag>,
    /// Scheme options.
    pub options: SchemeOptions,
    /// Group/object names; `face_groups[i]` indexes into this.
    pub groups: Vec<String>,
    /// Group of each face (empty means: all faces in no group).
    pub face_groups: Vec<u32>,
    /// 1-based source line of each vertex (empty when not from a file).
    pub vertex_lines: Vec<u32>,
    /// 1-based source line of each face (empty when not from a file).
    pub face_lines: Vec<u32>,
}

impl PolygonSoup {
    /// A soup from positions and faces given as index lists.
    ///
    /// ```
    /// use subdiv_mesh::{PolygonSoup, Mesh};
    /// use glam::Vec3;
    /// let soup = PolygonSoup::from_faces(
    ///     vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
    ///     &[vec![0, 1, 2, 3]],
    /// );
    /// let mesh = Mesh::from_soup(&soup).unwrap();
    /// assert_eq!(mesh.num_faces(), 1);
    /// ```
    pub fn from_faces<F: AsRef<[u32]>>(positions: Vec<Vec3>, faces: &[F]) -> Self {
        let mut soup = PolygonSoup { positions, ..Default::default() };
        for f in faces {
            soup.push_face(f.as_ref().iter().map(|&i| i as i64));
        }
        soup
    }

    /// Appends a face.
    pub fn push_face(&mut self, indices: impl IntoIterator<Item = i64>) {
        if self.face_offsets.is_empty() {
            self.face_offsets.push(0);
        }
        self.face_indices.extend(indices);
        self.face_offsets.push(self.face_indices.len() as u32);
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }

    /// The vertex indices of face `i`.
    pub fn face(&self, i: usize) -> &[i64] {
        &self.face_indices[self.face_offsets[i] as usize..self.face_offsets[i + 1] as usize]
    }

    /// Source line of face `i`, if known.
    pub fn face_line(&self, i: usize) -> Option<u32> {
        self.face_lines.get(i).copied()
    }

    /// Source line of vertex `i`, if known.
    pub fn vertex_line(&self, i: usize) -> Option<u32> {
        self.vertex_lines.get(i).copied()
    }
}
