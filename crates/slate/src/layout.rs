//! Per-mesh set-up: the list of patches and where every limit point goes in the output.
//!
//! A quad face whose 1-neighbourhood is all quads is one patch, gathered from the cage at
//! level 0. Any other face (an n-gon, or a quad next to one) becomes its level-1 quads, gathered
//! from a local level-1 refinement of the cage around such faces only.
//!
//! Output points are numbered once per mesh element so that a point shared by patches is stored
//! once: cage vertices first (in cage order), then one face point per level-1 face, the interior
//! points of every cage edge, the interior points of the inner edges of level-1 faces, and
//! finally each patch's interior. Every shared point has exactly one *owner* patch, which is the
//! only one that writes it; the others only reference it. This makes shared points bit-identical
//! by construction and the output independent of the number of threads.

use subdiv_mesh::{FaceId, HalfedgeId, Mesh, VertexId};
use subdiv_rules::RulesError;

use crate::patches::{irregular_faces, local_level1};

/// Where the points along one side of a patch go: the point at parameter index `s`
/// (`1..n`) along the side has id `first + (s - 1) * step`.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SideMap {
    pub first: u32,
    pub step: i32,
    pub owned: bool,
}

impl SideMap {
    #[inline]
    pub fn id(&self, s: u32) -> u32 {
        (self.first as i64 + (s as i64 - 1) * self.step as i64) as u32
    }
}

/// One patch: a quad of the cage (level 0) or of the local level-1 mesh.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Patch {
    /// Face of the mesh the patch is gathered from (the cage, or the level-1 mesh).
    pub face: FaceId,
    /// 0: gathered from the cage; 1: from the level-1 mesh.
    pub level: u8,
    /// Output ids of the four corners.
    pub corners: [u32; 4],
    pub corner_owned: [bool; 4],
    pub sides: [SideMap; 4],
    /// First output id of the interior points.
    pub interior: u32,
    /// `false` for patches of holes (computed for the points they own, never drawn).
    pub visible: bool,
}

/// The patches of a mesh for one uniform depth, and the output numbering.
#[derive(Debug)]
pub struct PatchLayout {
    pub(crate) depth: u32,
    pub(crate) patches: Vec<Patch>,
    pub(crate) num_points: u32,
    pub(crate) level1: Option<Mesh>,
    pub(crate) isolated: Vec<VertexId>,
    pub(crate) max_valence: usize,
}

impl PatchLayout {
    /// Number of patches (visible or not).
    pub fn num_patches(&self) -> usize {
        self.patches.len()
    }
    /// Number of output points.
    pub fn num_points(&self) -> usize {
        self.num_points as usize
    }
    /// Number of output quads.
    pub fn num_quads(&self) -> usize {
        let per = |p: &Patch| {
            let n = 1usize << (self.depth - p.level as u32);
            n * n
        };
        self.patches.iter().filter(|p| p.visible).map(per).sum()
    }
    /// Largest vertex valence of the cage (sizes the slates' corner arrays).
    pub fn max_valence(&self) -> usize {
        self.max_valence
    }
}

impl PatchLayout {
    /// Builds the patch list and output numbering of `mesh` for uniform depth `depth >= 1`.
    pub fn new(mesh: &Mesh, depth: u32) -> Result<PatchLayout, RulesError> {
        assert!(
            depth >= 1,
            "PatchLayout needs depth >= 1 (depth 0 is the cage itself)"
        );
        let irregular = irregular_faces(mesh);
        let any_irregular = irregular.iter().any(|&x| x);
        let (level1, first_child) = if any_irregular {
            let (m, fc) = local_level1(mesh, &irregular, 4)?;
            (Some(m), fc)
        } else {
            (None, Vec::new())
        };
        let m = 1u32 << depth; // samples per cage edge
        let m1 = m / 2; // samples per level-1 edge

        // Output numbering.
        let nv = mesh.num_vertices() as u32;
        let mut next = nv;
        let mut face_point = vec![u32::MAX; mesh.num_faces()];
        for f in mesh.faces() {
            if irregular[f.idx()] {
                face_point[f.idx()] = next;
                next += 1;
            }
        }
        let edge_base = next;
        next += mesh.num_edges() as u32 * (m - 1);
        let mut inner_edge = vec![u32::MAX; mesh.num_faces()];
        for f in mesh.faces() {
            if irregular[f.idx()] {
                inner_edge[f.idx()] = next;
                next += mesh.face_size(f) as u32 * (m1.saturating_sub(1));
            }
        }
        let edge_start = |h: HalfedgeId| edge_base + h.edge().0 * (m - 1);
        let forward = |h: HalfedgeId| h == h.edge().halfedge(0);

        // Owners.
        let edge_owner_face = |h: HalfedgeId| -> FaceId {
            let e = h.edge();
            let f0 = mesh.face(e.halfedge(0));
            if f0.is_some() {
                f0
            } else {
                mesh.face(e.halfedge(1))
            }
        };
        let vertex_owner = |v: VertexId| -> (FaceId, usize) {
            let h = mesh.vertex_halfedge(v);
            let f = mesh.face(h);
            let k = mesh
                .face_vertices(f)
                .iter()
                .position(|&x| x == v)
                .unwrap_or(0);
            (f, k)
        };
        let hidden = |f: FaceId| {
            mesh.is_hole(f)
                || (mesh.options().boundary == subdiv_mesh::BoundaryInterpolation::None
                    && mesh
                        .face_vertices(f)
                        .iter()
                        .any(|&v| mesh.is_boundary_vertex(v)))
        };

        let mut patches = Vec::new();
        for f in mesh.faces() {
            let hs: Vec<HalfedgeId> = {
                let h0 = mesh.face_halfedge(f);
                let mut v = vec![h0];
                let mut h = mesh.next(h0);
                while h != h0 {
                    v.push(h);
                    h = mesh.next(h);
                }
                v
            };
            let n = hs.len();
            let vs = mesh.face_vertices(f);
            if !irregular[f.idx()] {
                let mut corners = [0u32; 4];
                let mut corner_owned = [false; 4];
                let mut sides = [SideMap::default(); 4];
                for k in 0..4 {
                    corners[k] = vs[k].0;
                    corner_owned[k] = vertex_owner(vs[k]) == (f, k);
                    let h = hs[k];
                    let (first, step) = if forward(h) {
                        (edge_start(h), 1)
                    } else {
                        (edge_start(h) + (m - 2), -1)
                    };
                    sides[k] = SideMap {
                        first,
                        step,
                        owned: edge_owner_face(h) == f,
                    };
                }
                let interior = next;
                next += (m - 1) * (m - 1);
                patches.push(Patch {
                    face: f,
                    level: 0,
                    corners,
                    corner_owned,
                    sides,
                    interior,
                    visible: !hidden(f),
                });
            } else {
                for k in 0..n {
                    let h = hs[k];
                    let hp = hs[(k + n - 1) % n];
                    let mid = |h: HalfedgeId| edge_start(h) + (m / 2 - 1);
                    let owner_f = edge_owner_face(h);
                    let corners = [vs[k].0, mid(h), face_point[f.idx()], mid(hp)];
                    let corner_owned = [vertex_owner(vs[k]) == (f, k), owner_f == f, k == 0, false];
                    let s0 = if forward(h) {
                        SideMap {
                            first: edge_start(h),
                            step: 1,
                            owned: owner_f == f,
                        }
                    } else {
                        SideMap {
                            first: edge_start(h) + (m - 2),
                            step: -1,
                            owned: owner_f == f,
                        }
                    };
                    let s1 = SideMap {
                        first: inner_edge[f.idx()] + k as u32 * (m1.saturating_sub(1)),
                        step: 1,
                        owned: true,
                    };
                    let s2 = SideMap {
                        first: inner_edge[f.idx()]
                            + ((k + n - 1) % n) as u32 * (m1.saturating_sub(1))
                            + m1.saturating_sub(2),
                        step: -1,
                        owned: false,
                    };
                    let s3 = if forward(hp) {
                        SideMap {
                            first: edge_start(hp) + m / 2,
                            step: 1,
                            owned: edge_owner_face(hp) == f,
                        }
                    } else {
                        SideMap {
                            first: (edge_start(hp) + m / 2).wrapping_sub(2),
                            step: -1,
                            owned: edge_owner_face(hp) == f,
                        }
                    };
                    let interior = next;
                    next += (m1.saturating_sub(1)) * (m1.saturating_sub(1));
                    patches.push(Patch {
                        face: FaceId(first_child[f.idx()] + k as u32),
                        level: 1,
                        corners,
                        corner_owned,
                        sides: [s0, s1, s2, s3],
                        interior,
                        visible: !hidden(f),
                    });
                }
            }
        }
        let isolated = mesh.vertices().filter(|&v| mesh.is_isolated(v)).collect();
        Ok(PatchLayout {
            depth,
            patches,
            num_points: next,
            level1,
            isolated,
            max_valence: mesh
                .max_valence()
                .max(level1_max_valence(any_irregular, mesh)),
        })
    }
}

fn level1_max_valence(any: bool, mesh: &Mesh) -> usize {
    // A level-1 face point has the valence of its face.
    if any {
        mesh.faces().map(|f| mesh.face_size(f)).max().unwrap_or(4)
    } else {
        4
    }
}
