//! Face-varying data: one value per face corner, shared between corners by index (OBJ `vt`
//! with `f v/vt`). Corners of the faces around a vertex that use different indices make a
//! *seam*: the data is discontinuous there while the surface is not.

use glam::Vec2;

/// A face-varying channel of 2D values (texture coordinates).
///
/// `indices[c]` is the value of face corner `c`, with corners numbered as the mesh numbers them
/// (face `f` owns corners `face_offsets[f]..face_offsets[f + 1]`, in the order of
/// [`Mesh::face_vertices`](crate::Mesh::face_vertices)). Invariant: every index is below
/// `values.len()` (checked by [`Mesh::from_soup`](crate::Mesh::from_soup)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceVarying {
    /// The values.
    pub values: Vec<Vec2>,
    /// The value of every face corner.
    pub indices: Vec<u32>,
    /// Per value, its [`Dependence`] at this level of refinement. Empty for a cage's own
    /// channel, where it follows from the cage's topology; refinement fills it, since from
    /// then on it depends on the levels before.
    pub dependence: Vec<Dependence>,
}

/// Whether a face-varying value is held as a corner by OpenSubdiv's *dependent sharpness*
/// (`Vtr::FVarLevel::ValueTag::_depSharp`). With `cornersPlus1` or `cornersPlus2`, where two
/// values meet at a vertex and only one of their spans of faces has semi-sharp edges, the
/// other value is held in place with it while that sharpness lasts, and one level more where
/// the vertex keeps other semi-sharp edges.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum Dependence {
    /// Refined by its own span's rules.
    #[default]
    Free,
    /// Held while the other value's span stays semi-sharp.
    Held,
    /// Held for this last level after the other value's span ran out; a crease from the next.
    Released,
}

impl FaceVarying {
    /// The value at face corner `c`.
    #[inline]
    pub fn corner(&self, c: usize) -> Vec2 {
        self.values[self.indices[c] as usize]
    }
}

/// OpenSubdiv's face-varying linear interpolation (`Sdc::Options::FVarLinearInterpolation`),
/// in the numbering of the OBJ tag `t facevaryinginterpolateboundary 1/0/0 k`.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum FVarLinearInterpolation {
    /// 0: smooth everywhere; seams and boundaries are smooth creases.
    None,
    /// 1: sharpen corners only (the default, as in OpenSubdiv).
    #[default]
    CornersOnly,
    /// 2: also sharpen junctions of three or more seams.
    CornersPlus1,
    /// 3: also sharpen darts and both sides of a seam where one is a corner.
    CornersPlus2,
    /// 4: linear along seams and boundaries, smooth inside.
    Boundaries,
    /// 5: linear everywhere (bilinear).
    All,
}

impl FVarLinearInterpolation {
    /// Every option, in tag order.
    pub const ALL: [FVarLinearInterpolation; 6] = [
        FVarLinearInterpolation::None,
        FVarLinearInterpolation::CornersOnly,
        FVarLinearInterpolation::CornersPlus1,
        FVarLinearInterpolation::CornersPlus2,
        FVarLinearInterpolation::Boundaries,
        FVarLinearInterpolation::All,
    ];

    /// The option of tag value `k` (0..=5).
    pub fn from_tag(k: i64) -> Option<FVarLinearInterpolation> {
        usize::try_from(k)
            .ok()
            .and_then(|k| Self::ALL.get(k).copied())
    }

    /// The tag value of this option.
    pub fn tag(self) -> u32 {
        Self::ALL.iter().position(|&o| o == self).unwrap_or(1) as u32
    }

    /// OpenSubdiv's (and USD's `faceVaryingLinearInterpolation`) name.
    pub fn name(self) -> &'static str {
        match self {
            FVarLinearInterpolation::None => "none",
            FVarLinearInterpolation::CornersOnly => "cornersOnly",
            FVarLinearInterpolation::CornersPlus1 => "cornersPlus1",
            FVarLinearInterpolation::CornersPlus2 => "cornersPlus2",
            FVarLinearInterpolation::Boundaries => "boundaries",
            FVarLinearInterpolation::All => "all",
        }
    }
}
