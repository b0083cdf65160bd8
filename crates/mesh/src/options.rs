//! Scheme options carried by a mesh (OpenSubdiv's `Sdc::Options` subset that affects geometry).

/// How boundary edges and vertices are interpolated (OpenSubdiv `VtxBoundaryInterpolation`).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum BoundaryInterpolation {
    /// Boundary faces are not part of the limit surface; they only shape their neighbours.
    None,
    /// Boundary edges are infinitely sharp creases (the default, as in OpenSubdiv's OBJ shapes).
    #[default]
    EdgeOnly,
    /// Boundary edges are sharp and vertices with a single incident face are sharp corners.
    EdgeAndCorner,
}

/// How semi-sharp crease values decay from level to level (OpenSubdiv `CreasingMethod`).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum CreaseMethod {
    /// Sharpness drops by one per level (DeRose, Kass, Truong 1998).
    #[default]
    Uniform,
    /// Chaikin's curve rule applied to sharpness along a crease: 3/4 own + 1/4 neighbours' average.
    Chaikin,
}

/// The Catmull-Clark edge rule next to triangles (OpenSubdiv `TriangleSubdivision`).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum TriangleSubdivision {
    /// The plain Catmull-Clark rules for every face (OpenSubdiv `TRI_SUB_CATMARK`).
    #[default]
    Catmark,
    /// OpenSubdiv's "smooth triangle" weights (`TRI_SUB_SMOOTH`): a smooth edge point next to a
    /// triangle weighs the two face points more (see `subdiv_rules::catmark::edge_face_weight`).
    Smooth,
}

/// The options of a subdivision mesh.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct SchemeOptions {
    /// Boundary interpolation rule.
    pub boundary: BoundaryInterpolation,
    /// Crease decay rule.
    pub crease: CreaseMethod,
    /// Catmull-Clark edge rule next to triangles.
    pub triangles: TriangleSubdivision,
    /// Face-varying linear interpolation (how UVs are refined at seams and boundaries).
    pub fvar: crate::FVarLinearInterpolation,
}

/// Sharpness at or above this value is infinite (OpenSubdiv `SHARPNESS_INFINITE`).
pub const SHARPNESS_INFINITE: f32 = 10.0;
