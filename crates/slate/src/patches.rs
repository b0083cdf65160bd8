//! The static patch structure of a mesh: one *unit* per cage face, made of one patch (a quad
//! with an all-quad neighbourhood, gathered from the cage) or of the face's level-1 quads
//! (gathered from a local level-1 refinement around such faces only).

use subdiv_mesh::{FaceId, HalfedgeId, Mesh, VertexId};
use subdiv_rules::{Depth, RefineKernel, RulesError, Scheme, SeamCurves, refine_uniform};

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

/// What a local level-1 refinement is refined from: the sub-mesh of the cage's faces it covers
/// and the cage vertex of each of its vertices, to refine it again when the cage's positions
/// move (the level-1 points are positions; everything else of a layout is topology).
#[derive(Clone, Debug)]
pub(crate) struct Level1Source {
    sub: Mesh,
    cage_vertex: Vec<VertexId>,
}

impl Level1Source {
    /// Moves the points of `level1` (this source's refinement) to the refinement of `cage`'s
    /// positions: bit for bit what [`local_level1`] gives for `cage`, whose topology is the one
    /// this source was made from.
    pub(crate) fn move_to(&mut self, cage: &Mesh, level1: &mut Mesh) {
        for (p, &v) in self.sub.positions_mut().iter_mut().zip(&self.cage_vertex) {
            *p = cage.position(v);
        }
        let sub = &self.sub;
        let fp: Vec<glam::Vec3> = sub.faces().map(|f| sub.face_centroid(f)).collect();
        let points = RefineKernel::new(sub, Scheme::CatmullClark).refine_points(&fp);
        level1.positions_mut().copy_from_slice(&points);
    }
}

/// The level-1 refinement of the faces within `rings` vertex-rings of the irregular faces, for
/// each cage face the index of its first child face in it (`u32::MAX` if not refined), and what
/// it was refined from.
pub(crate) fn local_level1(
    mesh: &Mesh,
    irregular: &[bool],
    rings: usize,
) -> Result<(Mesh, Vec<u32>, Level1Source), RulesError> {
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
    // A crease copy's points are the crease rule's over edges of other copies
    // (`Mesh::crease_ends`), in other pieces: those copies' faces are refined too.
    if mesh.crease_ends_all().next().is_some() {
        let mut masters = Vec::new();
        for f in mesh.faces().filter(|f| keep[f.idx()]) {
            for &v in mesh.face_vertices(f) {
                masters.extend(
                    mesh.crease_ends(v)
                        .into_iter()
                        .flatten()
                        .map(|h| mesh.from(h)),
                );
            }
        }
        for m in masters {
            for h in mesh.outgoing(m) {
                let f = mesh.face(h);
                if f.is_some() {
                    keep[f.idx()] = true;
                }
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
            if let Some(whole) = mesh.whole_vertex_edges(v) {
                sub.set_whole_vertex_edges(VertexId(vmap[v.idx()]), whole);
            }
            if let Some(ends) = mesh.crease_ends(v) {
                let at = |w: VertexId| Some(VertexId(vmap[w.idx()])).filter(|x| x.0 != u32::MAX);
                let find = |h| sub.find_halfedge(at(mesh.from(h))?, at(mesh.to(h))?);
                if let [Some(a), Some(b)] = ends.map(find) {
                    sub.set_crease_ends(VertexId(vmap[v.idx()]), Some([a, b]));
                }
            }
        }
    }
    let level1 = refine_uniform(&sub, Scheme::CatmullClark)?;
    let mut cage_vertex = vec![VertexId(0); sub.num_vertices()];
    for v in mesh.vertices() {
        if vmap[v.idx()] != u32::MAX {
            cage_vertex[vmap[v.idx()] as usize] = v;
        }
    }
    Ok((level1, first_child, Level1Source { sub, cage_vertex }))
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
    /// The face it is gathered from, in the cage or in the level-1 mesh (a bilinear set has no
    /// level-1 mesh: its level-1 patches name their cage face, and `sub` the quad within it).
    pub src_face: FaceId,
}

/// The patches of a mesh, computed once per mesh (they depend only on its topology).
#[derive(Debug, Clone)]
pub struct PatchSet {
    pub(crate) level1: Option<Mesh>,
    level1_source: Option<Level1Source>,
    units: Vec<Unit>,
    patches: Vec<PatchRef>,
    max_valence: usize,
    /// The cage's seams (copies of non-manifold edges; [`PatchSet::write_seam_points`]).
    seams: SeamCurves,
    /// Catmull-Clark, or bilinear (each patch the bilinear patch of its source face).
    scheme: Scheme,
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
        PatchSet::with_scheme(mesh, Scheme::CatmullClark)
    }

    /// [`PatchSet::new`] for the bilinear surface: the same units and patches, each the bilinear
    /// patch of a cage quad or of a level-1 quad of the bilinear refinement (a corner, two edge
    /// midpoints and the face's centroid), which [`PatchGrids`](crate::PatchGrids) tessellates
    /// from the cage as [`crate::tessellate_bilinear`] does.
    pub fn bilinear(mesh: &Mesh) -> Result<PatchSet, RulesError> {
        PatchSet::with_scheme(mesh, Scheme::Bilinear)
    }

    /// `scheme` is Catmull-Clark or bilinear (Loop has its own layout, [`crate::TriLayout`]).
    fn with_scheme(mesh: &Mesh, scheme: Scheme) -> Result<PatchSet, RulesError> {
        let bilinear = scheme == Scheme::Bilinear;
        // A bilinear quad is one patch whatever its neighbours; other faces are level-1 quads.
        let irregular = if bilinear {
            mesh.faces().map(|f| mesh.face_size(f) != 4).collect()
        } else {
            irregular_faces(mesh)
        };
        let (level1, first_child, level1_source) = if !bilinear && irregular.iter().any(|&x| x) {
            let (m, fc, source) = local_level1(mesh, &irregular, 4)?;
            (Some(m), fc, Some(source))
        } else {
            (None, Vec::new(), None)
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
                    let src_face = if bilinear {
                        f
                    } else {
                        FaceId(first_child[f.idx()] + k)
                    };
                    patches.push(PatchRef {
                        unit: u,
                        sub: k,
                        level: 1,
                        src_face,
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
            level1_source,
            units,
            patches,
            max_valence: mesh.max_valence().max(face_max),
            seams: SeamCurves::new(mesh),
            scheme,
        })
    }

    /// The scheme of the patches: Catmull-Clark or bilinear.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// After the cage's positions moved (its topology the same as when the set was made):
    /// refines the local level-1 points again, so that the patches gathered from them follow.
    pub fn move_to(&mut self, mesh: &Mesh) {
        if let (Some(source), Some(level1)) = (&mut self.level1_source, &mut self.level1) {
            source.move_to(mesh, level1);
        }
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

    /// The cage's seams: the copies of its non-manifold edges.
    pub fn seams(&self) -> &SeamCurves {
        &self.seams
    }

    /// Overwrites the points of patch `p`'s grid at `depth` (`pos`, row by row as
    /// [`PatchGrids::grid`](crate::PatchGrids::grid) writes it) that lie on the cage's seams
    /// with [`SeamCurves`]' values, the same bits in every copy of a non-manifold edge, at any
    /// depth and from any side, so the pieces of a non-manifold cage meet exactly. Nothing
    /// changes for a cage without seams.
    pub fn write_seam_points(&self, mesh: &Mesh, p: &PatchRef, depth: Depth, pos: &mut [[f32; 3]]) {
        let seams = &self.seams;
        // Bilinear seam points are the same `a (1 - t) + b t` in every copy already.
        if seams.is_empty() || self.scheme == Scheme::Bilinear {
            return;
        }
        let n = 1u32 << depth;
        let at = |i: u32, j: u32| (j * (n + 1) + i) as usize;
        let face = self.units[p.unit as usize].face;
        let size = mesh.face_size(face);
        let h0 = mesh.face_halfedge(face);
        let hs = |k: usize| -> HalfedgeId {
            let mut h = h0;
            for _ in 0..k % size {
                h = mesh.next(h);
            }
            h
        };
        let mut put = |k: usize, q: Option<glam::Vec3>| {
            if let Some(q) = q {
                pos[k] = q.to_array();
            }
        };
        if p.level == 0 {
            // Corners (0,0), (n,0), (n,n), (0,n) at the face's vertices; side k along hs(k).
            let ends = [(0, 0), (n, 0), (n, n), (0, n)];
            for (k, &(i, j)) in ends.iter().enumerate() {
                put(at(i, j), seams.vertex_point(mesh, mesh.from(hs(k))));
            }
            for k in 0..4 {
                let h = hs(k);
                for s in 1..n {
                    let (i, j) = crate::side_point(k, s, n);
                    put(at(i, j), seams.point(mesh, h, s, depth));
                }
            }
        } else {
            // Level-1 quad `sub` of the face: corner (0,0) at the face's vertex `sub`, side
            // (i, 0) along the first half of hs(sub), side (0, j) back along the second half of
            // the previous edge.
            let k = p.sub as usize;
            let (h, hp) = (hs(k), hs(k + size - 1));
            put(at(0, 0), seams.vertex_point(mesh, mesh.from(h)));
            for s in 1..=n {
                put(at(s, 0), seams.point(mesh, h, s, depth + 1));
                put(at(0, s), seams.point(mesh, hp, 2 * n - s, depth + 1));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_meshes::{cube, grid, pentagon_flower, pentagonal_prism, single_quad};

    /// Units are one per face in face order, and their patch ranges tile the patch list.
    fn check_units(mesh: &Mesh, set: &PatchSet) {
        assert_eq!(set.units().len(), mesh.num_faces());
        let mut next = 0;
        for (u, (unit, f)) in set.units().iter().zip(mesh.faces()).enumerate() {
            assert_eq!(unit.face, f);
            assert_eq!(unit.first_patch, next);
            next += unit.patch_count;
            let range = unit.first_patch as usize..(unit.first_patch + unit.patch_count) as usize;
            for (k, p) in set.patches()[range].iter().enumerate() {
                assert_eq!((p.unit, p.sub), (u as u32, k as u32));
                assert_eq!(p.level, unit.irregular as u8);
            }
        }
        assert_eq!(next as usize, set.patches().len());
    }

    #[test]
    fn one_unit_per_face() {
        for mesh in [
            single_quad(),
            cube(),
            grid(3),
            pentagon_flower(),
            pentagonal_prism(),
        ] {
            check_units(&mesh, &PatchSet::new(&mesh).unwrap());
        }
    }

    #[test]
    fn regular_grid_is_gathered_from_the_cage() {
        let mesh = grid(3);
        let set = PatchSet::new(&mesh).unwrap();
        assert!(set.level1.is_none(), "no level-1 mesh without n-gons");
        assert_eq!(set.patches().len(), 9);
        for (unit, p) in set.units().iter().zip(set.patches()) {
            assert!(!unit.irregular);
            assert_eq!(unit.patch_count, 1);
            assert_eq!((p.level, p.src_face), (0, unit.face));
            assert!(std::ptr::eq(set.source(&mesh, p), &mesh));
        }
        assert_eq!(set.max_valence(), 4);
    }

    #[test]
    fn ngons_and_their_neighbours_get_level1_units() {
        let mesh = pentagon_flower();
        let set = PatchSet::new(&mesh).unwrap();
        let level1 = set
            .level1
            .as_ref()
            .expect("a level-1 mesh for the pentagon");
        for unit in set.units() {
            let f = unit.face.idx();
            // Face 0 is the pentagon, 1..=5 touch it, 6..=10 do not.
            assert_eq!(unit.irregular, f <= 5, "face {f}");
            let expected = if f <= 5 { mesh.face_size(unit.face) } else { 1 };
            assert_eq!(unit.patch_count as usize, expected, "face {f}");
        }
        assert_eq!(set.patches().len(), 5 + 5 * 4 + 5);
        assert_eq!(set.max_valence(), 5);
        for p in set.patches() {
            let unit = set.units()[p.unit as usize];
            let src = set.source(&mesh, p);
            if p.level == 0 {
                assert!(std::ptr::eq(src, &mesh));
                continue;
            }
            assert!(std::ptr::eq(src, level1));
            // Level-1 quad `sub` of a face starts at the child of the face's corner `sub`: of
            // its four vertices, the first is the nearest to that cage vertex.
            assert_eq!(level1.face_size(p.src_face), 4);
            let corner = mesh.position(mesh.face_vertices(unit.face)[p.sub as usize]);
            let dist: Vec<f32> = level1
                .face_vertices(p.src_face)
                .iter()
                .map(|&v| level1.position(v).distance(corner))
                .collect();
            assert!(
                dist[1..].iter().all(|&d| d > dist[0]),
                "face {} sub {}: {dist:?}",
                unit.face.idx(),
                p.sub
            );
        }
    }

    #[test]
    fn every_face_of_a_prism_is_irregular() {
        // Every quad of a pentagonal prism touches a pentagon.
        let mesh = pentagonal_prism();
        let set = PatchSet::new(&mesh).unwrap();
        assert!(set.units().iter().all(|u| u.irregular));
        assert_eq!(set.patches().len(), 2 * 5 + 5 * 4);
    }
}
