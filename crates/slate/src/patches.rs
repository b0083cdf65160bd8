//! The static patch structure of a mesh: one *unit* per cage face, made of one patch (a quad
//! with an all-quad neighbourhood, gathered from the cage) or of the face's level-1 quads
//! (gathered from a local level-1 refinement around such faces only).

use subdiv_mesh::{FaceId, Mesh, VertexId};
use subdiv_rules::{RulesError, Scheme, refine_uniform};

/// `true` for faces that are tessellated through their level-1 quads.
pub(crate) fn irregular_faces(mesh: &Mesh) -> Vec<bool> {
    let mut near_ngon = vec![false; mesh.num_vertices()];
    for f in mesh.faces() {
        if mesh.face_size(f) != 4 {
            for v in mesh.face_vertices(f) {
                near_ngon[v.idx()] = true;
            }
        }
    }
    mesh.faces()
        .map(|f| mesh.face_size(f) != 4 || mesh.face_vertices(f).iter().any(|v| near_ngon[v.idx()]))
        .collect()
}

/// The level-1 refinement of the faces within `rings` vertex-rings of the irregular faces, and for
/// each cage face the index of its first child face in it (`u32::MAX` if not refined).
pub(crate) fn local_level1(
    mesh: &Mesh,
    irregular: &[bool],
    rings: usize,
) -> Result<(Mesh, Vec<u32>), RulesError> {
    let mut keep = irregular.to_vec();
    for _ in 0..rings {
        let mut vmark = vec![false; mesh.num_vertices()];
        for f in mesh.faces().filter(|f| keep[f.idx()]) {
            for v in mesh.face_vertices(f) {
                vmark[v.idx()] = true;
            }
        }
        for f in mesh.faces() {
            if mesh.face_vertices(f).iter().any(|v| vmark[v.idx()]) {
                keep[f.idx()] = true;
            }
        }
    }
    // Sub-mesh of the kept faces, with their sharpness.
    let mut vmap = vec![u32::MAX; mesh.num_vertices()];
    let mut soup = subdiv_mesh::PolygonSoup {
        options: mesh.options(),
        ..Default::default()
    };
    let mut first_child = vec![u32::MAX; mesh.num_faces()];
    let mut child_count = 0u32;
    for f in mesh.faces().filter(|f| keep[f.idx()]) {
        let mut idx = Vec::with_capacity(mesh.face_size(f));
        for v in mesh.face_vertices(f) {
            if vmap[v.idx()] == u32::MAX {
                vmap[v.idx()] = soup.positions.len() as u32;
                soup.positions.push(mesh.position(*v));
            }
            idx.push(vmap[v.idx()] as i64);
        }
        soup.push_face(idx);
        first_child[f.idx()] = child_count;
        child_count += mesh.face_size(f) as u32;
    }
    for e in mesh.edges() {
        let [a, b] = mesh.edge_vertices(e);
        let s = mesh.edge_sharpness(e);
        if s > 0.0
            && vmap[a.idx()] != u32::MAX
            && vmap[b.idx()] != u32::MAX
            && !mesh.is_boundary_edge(e)
        {
            // Only edges of kept faces exist in the sub-mesh.
            let kept = [e.halfedge(0), e.halfedge(1)].iter().any(|&h| {
                let f = mesh.face(h);
                f.is_some() && keep[f.idx()]
            });
            if kept {
                soup.creases.push(subdiv_mesh::CreaseTag {
                    a: vmap[a.idx()] as i64,
                    b: vmap[b.idx()] as i64,
                    sharpness: s,
                    line: None,
                });
            }
        }
    }
    for v in mesh.vertices() {
        let s = mesh.vertex_sharpness(v);
        if s > 0.0
            && vmap[v.idx()] != u32::MAX
            && !(mesh.is_boundary_vertex(v) && s >= subdiv_mesh::SHARPNESS_INFINITE)
        {
            soup.corners.push(subdiv_mesh::CornerTag {
                v: vmap[v.idx()] as i64,
                sharpness: s,
                line: None,
            });
        }
    }
    let mut sub = Mesh::from_soup(&soup).map_err(RulesError::Internal)?;
    // Boundary corners sharpened by EdgeAndCorner in the cage keep their sharpness; vertices that
    // are boundary only in the sub-mesh must not be sharpened: restore cage values.
    for v in mesh.vertices() {
        if vmap[v.idx()] != u32::MAX {
            sub.set_vertex_sharpness(VertexId(vmap[v.idx()]), mesh.vertex_sharpness(v));
        }
    }
    let level1 = refine_uniform(&sub, Scheme::CatmullClark)?;
    Ok((level1, first_child))
}

/// A cage face and the patches it is tessellated with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Unit {
    /// The cage face.
    pub face: FaceId,
    /// Index of its first patch in [`PatchSet::patches`].
    pub first_patch: u32,
    /// 1 for a regular quad, `n` for an `n`-gon or a quad next to one (its level-1 quads).
    pub patch_count: u32,
    /// `true` if the unit is made of level-1 quads.
    pub irregular: bool,
}

/// One patch: a quad of the cage (level 0) or of the local level-1 mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchRef {
    /// Unit (cage face) index.
    pub unit: u32,
    /// Index among the unit's patches (the corner `k` of the cage face for level-1 quads).
    pub sub: u32,
    /// 0: gathered from the cage; 1: from the level-1 mesh.
    pub level: u8,
    /// The face it is gathered from, in the cage or in the level-1 mesh.
    pub src_face: FaceId,
}

/// The patches of a mesh, computed once per mesh (they depend only on its topology).
#[derive(Debug, Clone)]
pub struct PatchSet {
    pub(crate) level1: Option<Mesh>,
    units: Vec<Unit>,
    patches: Vec<PatchRef>,
    max_valence: usize,
}

impl PatchSet {
    /// Builds the units and patches of `mesh`.
    ///
    /// ```
    /// use subdiv_mesh::{parse_obj, Mesh};
    /// use subdiv_slate::PatchSet;
    /// // A quad next to a triangle: both become their level-1 quads (4 + 3 patches).
    /// let m = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3 4\nf 2 5 3\n")?)?;
    /// let set = PatchSet::new(&m).unwrap();
    /// assert_eq!(set.units().len(), 2);
    /// assert_eq!(set.patches().len(), 7);
    /// # Ok::<(), subdiv_mesh::MeshError>(())
    /// ```
    pub fn new(mesh: &Mesh) -> Result<PatchSet, RulesError> {
        let irregular = irregular_faces(mesh);
        let (level1, first_child) = if irregular.iter().any(|&x| x) {
            let (m, fc) = local_level1(mesh, &irregular, 4)?;
            (Some(m), fc)
        } else {
            (None, Vec::new())
        };
        let mut units = Vec::with_capacity(mesh.num_faces());
        let mut patches = Vec::with_capacity(mesh.num_faces());
        for f in mesh.faces() {
            let u = units.len() as u32;
            if irregular[f.idx()] {
                let n = mesh.face_size(f) as u32;
                units.push(Unit {
                    face: f,
                    first_patch: patches.len() as u32,
                    patch_count: n,
                    irregular: true,
                });
                for k in 0..n {
                    patches.push(PatchRef {
                        unit: u,
                        sub: k,
                        level: 1,
                        src_face: FaceId(first_child[f.idx()] + k),
                    });
                }
            } else {
                units.push(Unit {
                    face: f,
                    first_patch: patches.len() as u32,
                    patch_count: 1,
                    irregular: false,
                });
                patches.push(PatchRef {
                    unit: u,
                    sub: 0,
                    level: 0,
                    src_face: f,
                });
            }
        }
        let face_max = mesh.faces().map(|f| mesh.face_size(f)).max().unwrap_or(4);
        Ok(PatchSet {
            level1,
            units,
            patches,
            max_valence: mesh.max_valence().max(face_max),
        })
    }

    /// One unit per cage face, in face order.
    pub fn units(&self) -> &[Unit] {
        &self.units
    }
    /// All patches, unit by unit.
    pub fn patches(&self) -> &[PatchRef] {
        &self.patches
    }
    /// The mesh patch `p` is gathered from (`mesh` is the cage).
    pub fn source<'a>(&'a self, mesh: &'a Mesh, p: &PatchRef) -> &'a Mesh {
        match (p.level, &self.level1) {
            (1, Some(l1)) => l1,
            _ => mesh,
        }
    }
    /// Largest valence a slate corner array must hold.
    pub fn max_valence(&self) -> usize {
        self.max_valence
    }
}
