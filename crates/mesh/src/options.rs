//! Scheme options carried by a mesh (OpenSubdiv's `Sdc::Options` subset that affects geometry).

/// How boundary edges and vertices are interpolated (OpenSubdiv `VtxBoundaryInterpolation`).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum BoundaryInterpolation {
    /// Faces at the boundary are not part of the limit surface (they only shape their
    /// neighbours): every face at a vertex with a boundary edge that is not tagged infinitely
    /// sharp is made a hole when the mesh is built (OpenSubdiv's rule, [`BoundaryNoneRule`]).
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

/// OpenSubdiv 3.5's rule for [`BoundaryInterpolation::None`]
/// (`Far::TopologyRefinerFactoryBase::prepareComponentTagsAndSharpness`, before boundary edges
/// are sharpened): every face at a vertex with a boundary edge (one face) whose *tagged*
/// sharpness is not infinite is hidden (a hole); a vertex whose boundary edges are all tagged
/// infinitely sharp hides nothing. The one home of the rule: `Mesh::from_soup` applies it to
/// manifold cages, `PolygonSoup::split_nonmanifold` to a non-manifold cage before cutting it.
#[derive(Clone, Debug)]
pub(crate) struct BoundaryNoneRule {
    /// Vertices with a boundary edge not tagged infinitely sharp.
    hiding: Vec<bool>,
}

impl BoundaryNoneRule {
    /// The rule over `num_vertices` vertices, no edge noted yet.
    pub(crate) fn new(num_vertices: usize) -> Self {
        Self {
            hiding: vec![false; num_vertices],
        }
    }

    /// Notes the edge `a`-`b` with `faces` faces and its tagged sharpness (as the cage's crease
    /// tags give it, before the boundary is sharpened).
    #[inline]
    pub(crate) fn edge(&mut self, a: usize, b: usize, faces: usize, tagged_sharpness: f32) {
        if faces == 1 && tagged_sharpness < SHARPNESS_INFINITE {
            self.hiding[a] = true;
            self.hiding[b] = true;
        }
    }

    /// Whether the face with vertices `face` is hidden.
    #[inline]
    pub(crate) fn hides(&self, mut face: impl Iterator<Item = usize>) -> bool {
        face.any(|v| self.hiding[v])
    }
}
