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
use subdiv_rules::{Depth, RulesError, SeamCurves, TopologyKey};

use crate::gather::{GatherPlan, PlanEdge};
use crate::patches::{Level1Source, irregular_faces, local_level1};

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
    pub(crate) depth: Depth,
    pub(crate) patches: Vec<Patch>,
    /// How each patch is gathered (parallel to `patches`), and the sharp edges they list.
    pub(crate) plans: Vec<GatherPlan>,
    pub(crate) plan_edges: Vec<PlanEdge>,
    pub(crate) num_points: u32,
    pub(crate) level1: Option<Mesh>,
    level1_source: Option<Level1Source>,
    pub(crate) isolated: Vec<VertexId>,
    pub(crate) max_valence: usize,
    /// The UVs of the first tessellation with UVs, for the calls that follow (`uv.rs`).
    pub(crate) uv_cache: crate::uv::UvCache,
    /// First id of the interior points of cage edges (`2^depth - 1` per edge, in edge order,
    /// along the edge's even half-edge).
    pub(crate) edge_base: u32,
    /// The cage's seams (copies of non-manifold edges), whose points are written from their
    /// chains after the patches ([`PatchLayout::write_seam_points`]).
    pub(crate) seams: SeamCurves,
    /// This layout's identity: an output whose faces carry it keeps them (the quads and their
    /// offsets are a function of the layout alone, `tessellate_layout_into`).
    pub(crate) key: TopologyKey,
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
            let n = 1usize << (self.depth - p.level);
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
    pub fn new(mesh: &Mesh, depth: Depth) -> Result<PatchLayout, RulesError> {
        assert!(
            depth >= 1,
            "PatchLayout needs depth >= 1 (depth 0 is the cage itself)"
        );
        subdiv_rules::check_coordinates(mesh)?;
        let irregular = irregular_faces(mesh);
        let any_irregular = irregular.iter().any(|&x| x);
        let (level1, first_child, level1_source) = if any_irregular {
            let (m, fc, source) = local_level1(mesh, &irregular, 4)?;
            (Some(m), fc, Some(source))
        } else {
            (None, Vec::new(), None)
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
        let numbering = Numbering {
            mesh,
            m,
            m1,
            edge_base,
            face_point,
            inner_edge,
        };

        let mut patches = Vec::new();
        for f in mesh.faces() {
            let hs: Vec<HalfedgeId> = mesh.face_halfedges(f).collect();
            if !irregular[f.idx()] {
                patches.push(numbering.cage_patch(f, &hs, &mut next));
            } else {
                numbering.level1_patches(f, &hs, first_child[f.idx()], &mut next, &mut patches);
            }
        }
        let isolated = mesh.vertices().filter(|&v| mesh.is_isolated(v)).collect();
        let mut plan_edges = Vec::new();
        let plans = patches
            .iter()
            .map(|p| {
                let src = match (&level1, p.level) {
                    (Some(l1), 1) => l1,
                    _ => mesh,
                };
                GatherPlan::new(src, p.face, &mut plan_edges)
            })
            .collect();
        Ok(PatchLayout {
            depth,
            patches,
            plans,
            plan_edges,
            num_points: next,
            level1,
            level1_source,
            isolated,
            max_valence: mesh
                .max_valence()
                .max(level1_max_valence(any_irregular, mesh)),
            uv_cache: Default::default(),
            edge_base,
            seams: SeamCurves::new(mesh),
            key: TopologyKey::fresh(),
        })
    }
}

impl PatchLayout {
    /// After the cage's positions moved (its topology the same as when the layout was made):
    /// refines the local level-1 points of its n-gons and their neighbours again, which the
    /// patches there are gathered from (everything else of a layout is topology).
    pub fn move_to(&mut self, mesh: &Mesh) {
        if let (Some(source), Some(level1)) = (&mut self.level1_source, &mut self.level1) {
            source.move_to(mesh, level1);
        }
    }

    /// Overwrites the points on the cage's seams (the copies of a non-manifold edge and their
    /// end vertices) with [`SeamCurves`]' values, which are the same bits in every copy, so the
    /// pieces of a non-manifold cage meet exactly; every other point is left as the patches
    /// wrote it. Normals stay the patches' (at a seam the renderer takes each piece's own
    /// one-sided normal).
    pub(crate) fn write_seam_points(&self, mesh: &Mesh, positions: &mut [[f32; 3]]) {
        self.seams
            .write_uniform(mesh, self.depth, self.edge_base, positions);
    }
}

/// The output numbering of the points shared between patches, and who owns them.
struct Numbering<'a> {
    mesh: &'a Mesh,
    /// Samples per cage edge (`2^depth`).
    m: u32,
    /// Samples per level-1 edge (`m / 2`).
    m1: u32,
    /// First id of the interior points of cage edges (`m - 1` per edge, in edge order).
    edge_base: u32,
    /// Id of the face point of each irregular face.
    face_point: Vec<u32>,
    /// First id of the interior points of each irregular face's inner level-1 edges.
    inner_edge: Vec<u32>,
}

impl Numbering<'_> {
    fn edge_start(&self, h: HalfedgeId) -> u32 {
        self.edge_base + h.edge().0 * (self.m - 1)
    }

    fn forward(h: HalfedgeId) -> bool {
        h == h.edge().halfedge(0)
    }

    /// The face that owns the points of `h`'s edge.
    fn edge_owner_face(&self, h: HalfedgeId) -> FaceId {
        let e = h.edge();
        let f0 = self.mesh.face(e.halfedge(0));
        if f0.is_some() {
            f0
        } else {
            self.mesh.face(e.halfedge(1))
        }
    }

    /// The face and corner index that own vertex `v`.
    fn vertex_owner(&self, v: VertexId) -> (FaceId, usize) {
        let mesh = self.mesh;
        let h = mesh.vertex_halfedge(v);
        let f = mesh.face(h);
        let k = mesh
            .face_vertices(f)
            .iter()
            .position(|&x| x == v)
            .unwrap_or(0);
        (f, k)
    }

    /// `true` for faces whose patches are computed but not drawn.
    fn hidden(&self, f: FaceId) -> bool {
        self.mesh.is_hole(f)
    }

    /// The one patch of a regular quad `f` (half-edges `hs`), gathered from the cage; its
    /// interior takes the ids from `next` on.
    fn cage_patch(&self, f: FaceId, hs: &[HalfedgeId], next: &mut u32) -> Patch {
        let (m, vs) = (self.m, self.mesh.face_vertices(f));
        let mut corners = [0u32; 4];
        let mut corner_owned = [false; 4];
        let mut sides = [SideMap::default(); 4];
        for k in 0..4 {
            corners[k] = vs[k].0;
            corner_owned[k] = self.vertex_owner(vs[k]) == (f, k);
            let h = hs[k];
            let (first, step) = if Self::forward(h) {
                (self.edge_start(h), 1)
            } else {
                (self.edge_start(h) + (m - 2), -1)
            };
            sides[k] = SideMap {
                first,
                step,
                owned: self.edge_owner_face(h) == f,
            };
        }
        let interior = *next;
        *next += (m - 1) * (m - 1);
        Patch {
            face: f,
            level: 0,
            corners,
            corner_owned,
            sides,
            interior,
            visible: !self.hidden(f),
        }
    }

    /// The level-1 quads of face `f` (half-edges `hs`), the first of them face `first_child` of
    /// the level-1 mesh; their interiors take the ids from `next` on.
    fn level1_patches(
        &self,
        f: FaceId,
        hs: &[HalfedgeId],
        first_child: u32,
        next: &mut u32,
        patches: &mut Vec<Patch>,
    ) {
        let (m, m1, vs, n) = (self.m, self.m1, self.mesh.face_vertices(f), hs.len());
        let inner_edge = self.inner_edge[f.idx()];
        for k in 0..n {
            let h = hs[k];
            let hp = hs[(k + n - 1) % n];
            let mid = |h: HalfedgeId| self.edge_start(h) + (m / 2 - 1);
            let owner_f = self.edge_owner_face(h);
            let corners = [vs[k].0, mid(h), self.face_point[f.idx()], mid(hp)];
            let corner_owned = [
                self.vertex_owner(vs[k]) == (f, k),
                owner_f == f,
                k == 0,
                false,
            ];
            let s0 = if Self::forward(h) {
                SideMap {
                    first: self.edge_start(h),
                    step: 1,
                    owned: owner_f == f,
                }
            } else {
                SideMap {
                    first: self.edge_start(h) + (m - 2),
                    step: -1,
                    owned: owner_f == f,
                }
            };
            let s1 = SideMap {
                first: inner_edge + k as u32 * (m1.saturating_sub(1)),
                step: 1,
                owned: true,
            };
            let s2 = SideMap {
                first: inner_edge
                    + ((k + n - 1) % n) as u32 * (m1.saturating_sub(1))
                    + m1.saturating_sub(2),
                step: -1,
                owned: false,
            };
            let s3 = if Self::forward(hp) {
                SideMap {
                    first: self.edge_start(hp) + m / 2,
                    step: 1,
                    owned: self.edge_owner_face(hp) == f,
                }
            } else {
                SideMap {
                    first: (self.edge_start(hp) + m / 2).wrapping_sub(2),
                    step: -1,
                    owned: self.edge_owner_face(hp) == f,
                }
            };
            let interior = *next;
            *next += (m1.saturating_sub(1)) * (m1.saturating_sub(1));
            patches.push(Patch {
                face: FaceId(first_child + k as u32),
                level: 1,
                corners,
                corner_owned,
                sides: [s0, s1, s2, s3],
                interior,
                visible: !self.hidden(f),
            });
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_meshes::{cube, grid, pentagon_flower, pentagonal_prism, single_quad};
    use subdiv_rules::{Scheme, refine_uniform_levels};

    /// How many times each output id is written: once per owner, plus isolated vertices.
    fn write_counts(layout: &PatchLayout) -> Vec<u32> {
        let mut count = vec![0u32; layout.num_points()];
        for v in &layout.isolated {
            count[v.idx()] += 1;
        }
        for p in &layout.patches {
            let n = 1u32 << (layout.depth - p.level);
            for k in 0..4 {
                if p.corner_owned[k] {
                    count[p.corners[k] as usize] += 1;
                }
            }
            for side in p.sides.iter().filter(|s| s.owned) {
                for s in 1..n {
                    count[side.id(s) as usize] += 1;
                }
            }
            for x in 0..(n - 1) * (n - 1) {
                count[(p.interior + x) as usize] += 1;
            }
        }
        count
    }

    #[test]
    fn point_and_quad_counts_match_uniform_refinement() {
        for (name, mesh) in [
            ("quad", single_quad()),
            ("cube", cube()),
            ("grid", grid(3)),
            ("flower", pentagon_flower()),
            ("prism", pentagonal_prism()),
        ] {
            for depth in 1..=3 {
                let layout = PatchLayout::new(&mesh, depth).unwrap();
                let refined = refine_uniform_levels(&mesh, Scheme::CatmullClark, depth).unwrap();
                assert_eq!(
                    layout.num_points(),
                    refined.num_vertices(),
                    "{name} depth {depth}: points"
                );
                assert_eq!(
                    layout.num_quads(),
                    refined.num_faces(),
                    "{name} depth {depth}: quads"
                );
            }
        }
    }

    #[test]
    fn point_counts_follow_the_closed_formula() {
        // m = 2^depth samples per cage edge: V + E (m - 1) + the interior of every face, which
        // for an n-gon is its face point, n inner edges and n level-1 quads of side m / 2.
        let expected = |mesh: &Mesh, depth: Depth| {
            let m = 1usize << depth;
            let m1 = m / 2;
            let faces: usize = mesh
                .faces()
                .map(|f| match mesh.face_size(f) {
                    4 => (m - 1) * (m - 1),
                    n => 1 + n * (m1 - 1) + n * (m1 - 1) * (m1 - 1),
                })
                .sum();
            mesh.num_vertices() + mesh.num_edges() * (m - 1) + faces
        };
        assert_eq!(
            PatchLayout::new(&single_quad(), 2).unwrap().num_points(),
            25
        );
        assert_eq!(
            PatchLayout::new(&cube(), 3).unwrap().num_points(),
            6 * 64 + 2
        );
        for mesh in [single_quad(), cube(), pentagon_flower(), pentagonal_prism()] {
            for depth in 1..=4 {
                let layout = PatchLayout::new(&mesh, depth).unwrap();
                assert_eq!(layout.num_points(), expected(&mesh, depth), "depth {depth}");
            }
        }
    }

    #[test]
    fn every_output_point_has_exactly_one_owner() {
        for (name, mesh) in [
            ("quad", single_quad()),
            ("cube", cube()),
            ("grid", grid(3)),
            ("flower", pentagon_flower()),
            ("prism", pentagonal_prism()),
        ] {
            for depth in 1..=3 {
                let layout = PatchLayout::new(&mesh, depth).unwrap();
                let count = write_counts(&layout);
                let bad: Vec<usize> = (0..count.len()).filter(|&i| count[i] != 1).collect();
                assert!(
                    bad.is_empty(),
                    "{name} depth {depth}: ids {bad:?} not written once"
                );
                // Ids that are only referenced stay in range too.
                for p in &layout.patches {
                    assert!(p.corners.iter().all(|&c| (c as usize) < count.len()));
                }
            }
        }
    }

    #[test]
    fn patches_and_max_valence() {
        // One patch per regular quad, n per n-gon or quad next to one.
        let layout = PatchLayout::new(&cube(), 2).unwrap();
        assert_eq!(layout.num_patches(), 6);
        assert!(layout.level1.is_none());
        // Valence 3 everywhere, but never below 4 (a slate corner is at least a regular one).
        assert_eq!(layout.max_valence(), 4);
        let flower = pentagon_flower();
        let layout = PatchLayout::new(&flower, 2).unwrap();
        assert_eq!(layout.num_patches(), 5 + 5 * 4 + 5);
        assert!(layout.level1.is_some());
        assert_eq!(
            layout.max_valence(),
            5,
            "a level-1 face point of the pentagon"
        );
        let levels: Vec<u8> = layout.patches.iter().map(|p| p.level).collect();
        assert_eq!(levels.iter().filter(|&&l| l == 1).count(), 25);
        assert!(
            levels[25..].iter().all(|&l| l == 0),
            "outer ring from the cage"
        );
    }

    #[test]
    fn shared_points_are_shared_by_the_output_quads() {
        // With one id per shared point, the output is a closed quad mesh wherever the cage is:
        // every directed edge once, each with its reverse; Euler characteristic kept.
        for (name, mesh, euler) in [
            ("cube", cube(), 2),
            ("prism", pentagonal_prism(), 2),
            ("flower", pentagon_flower(), 1),
            ("grid", grid(2), 1),
        ] {
            for depth in 1..=3 {
                let layout = PatchLayout::new(&mesh, depth).unwrap();
                let out = crate::tessellate_layout(&mesh, &layout).unwrap();
                let mut directed = std::collections::HashSet::new();
                for f in 0..out.num_faces() {
                    let q = out.face(f);
                    for k in 0..q.len() {
                        let e = (q[k], q[(k + 1) % q.len()]);
                        assert!(directed.insert(e), "{name} depth {depth}: edge {e:?} twice");
                    }
                }
                let undirected: std::collections::HashSet<(u32, u32)> = directed
                    .iter()
                    .map(|&(a, b)| (a.min(b), a.max(b)))
                    .collect();
                if euler == 2 {
                    assert_eq!(directed.len(), 2 * undirected.len(), "{name}: closed");
                }
                let chi =
                    out.positions().len() as i64 - undirected.len() as i64 + out.num_faces() as i64;
                assert_eq!(chi, euler, "{name} depth {depth}: Euler characteristic");
            }
        }
    }
}
