//! The bilinear scheme on patches ([`tessellate_bilinear`]): the uniform depth-`d` tessellation
//! of OpenSubdiv's `SCHEME_BILINEAR`, whose limit surface is the bilinear patch of every quad
//! of the cage and of every level-1 quad of its other faces (`subdiv_rules::bilinear_patches`).
//!
//! No slate is needed: a patch's points are its bilinear interpolation at the level-`d`
//! parameters (bilinear subdivision reproduces the patch exactly), each point written by one
//! owner from the same inputs, so patches meet to the bit: a cage vertex its position, a point
//! inside a cage edge the edge's two ends (`a (1 - t) + b t`, the same terms from either side),
//! an n-gon's face point the centroid of its corners and a point on a level-1 edge inside the
//! n-gon its edge midpoint and the face point. Normals are the patches' derivatives (exact); a
//! point on two patches or more has each patch's normal at its corners there (one-sided, as on a
//! crease) and their mean as its own.

use glam::{Vec2, Vec3};
use subdiv_mesh::{FaceId, HalfedgeId, Mesh};
use subdiv_rules::{Depth, LimitMesh, MAX_DEPTH, Scheme, TopologyKey};

use crate::patches::PatchRef;
use crate::size::check_uniform_size;
use crate::tessellate::SlateError;

/// One bilinear patch: a quad of the cage, or level-1 quad `sub` of an n-gon.
#[derive(Clone, Copy, Debug)]
struct Patch {
    face: FaceId,
    /// Level-1 quad index within the n-gon; `u32::MAX` for a quad of the cage.
    sub: u32,
    /// First id of its interior points.
    interior: u32,
}

/// The output numbering of a uniform bilinear tessellation (`depth >= 1`): cage vertices
/// first, then `2^depth - 1` points inside each cage edge (along its half-edge 0), each
/// n-gon's face point and the points inside its level-1 edges, then each patch's interior.
#[derive(Debug)]
pub struct BilinearLayout {
    depth: Depth,
    edge_base: u32,
    /// Per face: its face point (n-gons; `u32::MAX` for quads).
    face_point: Vec<u32>,
    /// Per face: the first point inside its level-1 edges (n-gons).
    spoke_base: Vec<u32>,
    patches: Vec<Patch>,
    num_points: u32,
    visible_quads: usize,
    key: TopologyKey,
}

impl BilinearLayout {
    /// The numbering of `mesh` at `depth` (1 to [`MAX_DEPTH`]), refused beyond this machine's
    /// memory as any uniform tessellation.
    pub fn new(mesh: &Mesh, depth: Depth) -> Result<BilinearLayout, SlateError> {
        if depth == 0 || depth > MAX_DEPTH {
            return Err(SlateError::TooDeep {
                depth,
                max: MAX_DEPTH,
            });
        }
        check_uniform_size(mesh, Scheme::Bilinear, depth)?;
        let m = 1u32 << depth;
        let m1 = m / 2;
        let edge_base = mesh.num_vertices() as u32;
        let mut next = edge_base + mesh.num_edges() as u32 * (m - 1);
        let mut face_point = vec![u32::MAX; mesh.num_faces()];
        let mut spoke_base = vec![u32::MAX; mesh.num_faces()];
        for f in mesh.faces().filter(|&f| mesh.face_size(f) != 4) {
            face_point[f.idx()] = next;
            spoke_base[f.idx()] = next + 1;
            next += 1 + mesh.face_size(f) as u32 * (m1 - 1);
        }
        let mut patches = Vec::new();
        let mut visible_quads = 0;
        for f in mesh.faces() {
            let n = mesh.face_size(f) as u32;
            let (subs, side) = if n == 4 { (1, m) } else { (n, m1) };
            for k in 0..subs {
                patches.push(Patch {
                    face: f,
                    sub: if n == 4 { u32::MAX } else { k },
                    interior: next,
                });
                next += (side - 1) * (side - 1);
                if !mesh.is_hole(f) {
                    visible_quads += (side * side) as usize;
                }
            }
        }
        Ok(BilinearLayout {
            depth,
            edge_base,
            face_point,
            spoke_base,
            patches,
            num_points: next,
            visible_quads,
            key: TopologyKey::fresh(),
        })
    }

    /// Number of output points.
    pub fn num_points(&self) -> usize {
        self.num_points as usize
    }

    /// Number of patches (visible or not): the cage's quads and its other faces' level-1 quads.
    pub fn num_patches(&self) -> usize {
        self.patches.len()
    }

    /// The id of point `k` (0..=m, from the half-edge's origin) along half-edge `h`.
    fn on_edge(&self, h: HalfedgeId, k: u32, corner: [u32; 2]) -> u32 {
        let m = 1u32 << self.depth;
        match k {
            0 => corner[0],
            k if k == m => corner[1],
            k => {
                let e = h.edge();
                let along = if h == e.halfedge(0) { k } else { m - k };
                self.edge_base + e.0 * (m - 1) + along - 1
            }
        }
    }
}

/// A patch's corners (counter-clockwise from its parameter origin): points, ids, UVs.
struct Corners {
    p: [Vec3; 4],
    uv: Option<[Vec2; 4]>,
}

impl Corners {
    /// The patch point at `(u, v)`.
    #[inline]
    fn at(&self, u: f32, v: f32) -> Vec3 {
        let p = &self.p;
        p[0] * ((1.0 - u) * (1.0 - v))
            + p[1] * (u * (1.0 - v))
            + p[2] * (u * v)
            + p[3] * ((1.0 - u) * v)
    }

    /// The patch's unit normal at `(u, v)` (zero where its derivatives are parallel).
    #[inline]
    fn normal(&self, u: f32, v: f32) -> Vec3 {
        let p = &self.p;
        let du = (p[1] - p[0]) * (1.0 - v) + (p[2] - p[3]) * v;
        let dv = (p[3] - p[0]) * (1.0 - u) + (p[2] - p[1]) * u;
        du.cross(dv).normalize_or_zero()
    }

    #[inline]
    fn uv_at(&self, u: f32, v: f32) -> Option<Vec2> {
        let t = self.uv.as_ref()?;
        Some(
            t[0] * ((1.0 - u) * (1.0 - v))
                + t[1] * (u * (1.0 - v))
                + t[2] * (u * v)
                + t[3] * ((1.0 - u) * v),
        )
    }
}

/// The corners of a bilinear patch of face `f`, counter-clockwise from its parameter origin:
/// the quad's own (`sub` `None`), or those of the face's level-1 quad `sub` (its corner `sub`,
/// the midpoint of the edge after it, the face's centroid, the midpoint of the edge before it;
/// each midpoint `a (1 - t) + b t` at `t = 1/2`, the same bits from either face).
pub fn bilinear_patch_corners(mesh: &Mesh, f: FaceId, sub: Option<usize>) -> [Vec3; 4] {
    let vs = mesh.face_vertices(f);
    let m = vs.len();
    let at = |k: usize| mesh.position(vs[k % m]);
    match sub {
        None => [0, 1, 2, 3].map(at),
        Some(k) => {
            let centroid = (0..m).map(at).sum::<Vec3>() / m as f32;
            let v = at(k);
            [
                v,
                lerp(v, at(k + 1), 0.5),
                centroid,
                lerp(v, at(k + m - 1), 0.5),
            ]
        }
    }
}

/// The grid of bilinear patch `p` of the cage `mesh` at `depth`, as
/// [`crate::PatchGrids::grid`] writes a patch's grid: points and normals row by row (`i` along
/// the patch's first edge, `j` along its last edge reversed), and every border point's normal in
/// `sided` too (bilinear patches meet with a crease at every edge). Points are
/// [`tessellate_bilinear`]'s: on a cage edge `a (1 - t) + b t` of its ends (the same bits from
/// either face), on a level-1 edge inside an n-gon the same of its midpoint and the centroid.
pub(crate) fn patch_grid_sided(
    mesh: &Mesh,
    p: &PatchRef,
    depth: Depth,
    pos: &mut [[f32; 3]],
    nrm: &mut [[f32; 3]],
    sided: &mut Vec<(u32, [f32; 3])>,
) {
    let vs = mesh.face_vertices(p.src_face);
    let at = |k: usize| mesh.position(vs[k % vs.len()]);
    let n = 1u32 << depth;
    let s = n as f32;
    // The four sides' points at `t` along each side, as `(start, end, t scale)`: a cage edge
    // from the corner (scale 1/2 on an n-gon's level-1 quad), or a level-1 edge to the centroid.
    let sub = (p.level != 0).then_some(p.sub as usize);
    let corners = bilinear_patch_corners(mesh, p.src_face, sub);
    let c = corners;
    let sides = match sub {
        None => [
            (c[0], c[1], 1.0),
            (c[1], c[2], 1.0),
            (c[3], c[2], 1.0),
            (c[0], c[3], 1.0),
        ],
        Some(k) => {
            let (next, prev) = (at(k + 1), at(k + vs.len() - 1));
            [
                (c[0], next, 0.5),
                (c[1], c[2], 1.0),
                (c[3], c[2], 1.0),
                (c[0], prev, 0.5),
            ]
        }
    };
    let c = Corners {
        p: corners,
        uv: None,
    };
    let side = |k: usize, t: f32| {
        let (a, b, scale) = sides[k];
        lerp(a, b, t * scale)
    };
    sided.clear();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / s, j as f32 / s);
            let k = (j * (n + 1) + i) as usize;
            let point = match (i, j) {
                (_, 0) => side(0, u),
                (_, j) if j == n => side(2, u),
                (0, _) => side(3, v),
                (i, _) if i == n => side(1, v),
                _ => c.at(u, v),
            };
            let normal = c.normal(u, v).to_array();
            pos[k] = point.to_array();
            nrm[k] = normal;
            if i == 0 || j == 0 || i == n || j == n {
                sided.push((k as u32, normal));
            }
        }
    }
}

/// `a (1 - t) + b t`: the same bits from either end (`t` dyadic, `1 - t` exact).
#[inline]
fn lerp(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    a * (1.0 - t) + b * t
}

/// The uniform depth-`depth` tessellation of the bilinear limit surface of `mesh`: the quads of
/// the level-`depth` refinement, every point its own limit with the patches' normals (see the
/// module notes); vertex `i` below the cage's vertex count is cage vertex `i`. Depth 0 is the
/// cage itself.
///
/// ```
/// use subdiv_mesh::{parse_obj, Mesh};
/// let tri = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")?)?;
/// let t = subdiv_slate::tessellate_bilinear(&tri, 2).unwrap();
/// assert_eq!(t.num_faces(), 3 * 4);
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
pub fn tessellate_bilinear(mesh: &Mesh, depth: Depth) -> Result<LimitMesh, SlateError> {
    subdiv_rules::check_coordinates(mesh)?;
    if depth == 0 {
        return Ok(subdiv_rules::limit_surface(mesh, Scheme::Bilinear));
    }
    let layout = BilinearLayout::new(mesh, depth)?;
    let mut out = LimitMesh::default();
    tessellate_bilinear_into(mesh, &layout, &mut out)?;
    Ok(out)
}

/// [`tessellate_bilinear`] with its layout into a reused output: the quads are written once per
/// layout and output and kept by the calls that follow ([`LimitMesh::topology_written`]), the
/// points, normals and UVs written every call. `mesh` is the cage the layout was made for (its
/// positions may have moved).
pub fn tessellate_bilinear_into(
    mesh: &Mesh,
    layout: &BilinearLayout,
    out: &mut LimitMesh,
) -> Result<(), SlateError> {
    subdiv_rules::check_coordinates(mesh)?;
    let m = 1u32 << layout.depth;
    let np = layout.num_points();
    let w = out.write_keyed(layout.key, np, layout.visible_quads, 4)?;
    let (pos, nrm) = (w.positions, w.normals);
    let mut faces = w.faces;
    // Shared points: the sum of the patches' normals, and how many patches meet there.
    let mut shared: Vec<(Vec3, u32)> = vec![(Vec3::ZERO, 0); np];
    // Points of no visible patch (isolated vertices, points of holes only) have none.
    nrm.fill([0.0; 3]);
    for v in mesh.vertices() {
        pos[v.idx()] = mesh.position(v).to_array();
    }
    for e in mesh.edges() {
        let [a, b] = mesh.edge_vertices(e).map(|v| mesh.position(v));
        for k in 1..m {
            let id = layout.edge_base + e.0 * (m - 1) + k - 1;
            pos[id as usize] = lerp(a, b, k as f32 / m as f32).to_array();
        }
    }
    let uv = mesh.uv();
    let mut uvs: Vec<[f32; 2]> = Vec::new();
    // (corner, the patch's normal there, the point).
    let mut sided: Vec<(u32, [f32; 3], u32)> = Vec::new();
    let mut corner = 0u32;
    let mut hs: Vec<HalfedgeId> = Vec::new();
    for patch in &layout.patches {
        let f = patch.face;
        hs.clear();
        hs.extend(mesh.face_halfedges(f));
        let PatchGrid { c, side, ids } = patch_grid(mesh, layout, patch, &hs, pos);
        let s = side as f32;
        for j in 0..=side {
            for i in 0..=side {
                let (u, v) = (i as f32 / s, j as f32 / s);
                let id = ids(i, j) as usize;
                let inner = i > 0 && j > 0 && i < side && j < side;
                if inner {
                    pos[id] = c.at(u, v).to_array();
                    nrm[id] = c.normal(u, v).to_array();
                } else if !mesh.is_hole(f) {
                    let sn = &mut shared[id];
                    sn.0 += c.normal(u, v);
                    sn.1 += 1;
                }
            }
        }
        if mesh.is_hole(f) {
            continue;
        }
        for j in 0..side {
            for i in 0..side {
                let quad = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                for (q, &(a, b)) in quad.iter().enumerate() {
                    let id = ids(a, b);
                    if let Some(fs) = faces.as_deref_mut() {
                        fs[(corner + q as u32) as usize] = id;
                    }
                    let (u, v) = (a as f32 / s, b as f32 / s);
                    if let Some(t) = c.uv_at(u, v) {
                        uvs.push(t.to_array());
                    }
                    let edge = a == 0 || b == 0 || a == side || b == side;
                    if edge {
                        sided.push((corner + q as u32, c.normal(u, v).to_array(), id));
                    }
                }
                corner += 4;
            }
        }
    }
    for (id, &(sum, count)) in shared.iter().enumerate() {
        if count > 0 {
            nrm[id] = sum.normalize_or_zero().to_array();
        }
    }
    // One-sided normals only where two patches or more meet.
    let kinked = sided
        .into_iter()
        .filter(|&(_, _, id)| shared[id as usize].1 > 1)
        .map(|(c, n, _)| (c, n));
    out.write_corner_normals(kinked);
    if uv.is_some() {
        let idx = (0..uvs.len() as u32).collect();
        out.set_uvs(uvs, idx)?;
    }
    Ok(())
}

/// A patch's corners, side (quads per side) and the output id of each grid point `(i, j)`.
struct PatchGrid<'a> {
    c: Corners,
    side: u32,
    ids: Box<dyn Fn(u32, u32) -> u32 + 'a>,
}

/// The grid of `patch` (its face's half-edges `hs`, from corner 0); an n-gon's quad writes its
/// face point and the points inside its level-1 edge from its edge's midpoint into `pos`.
fn patch_grid<'a>(
    mesh: &'a Mesh,
    layout: &'a BilinearLayout,
    patch: &Patch,
    hs: &[HalfedgeId],
    pos: &mut [[f32; 3]],
) -> PatchGrid<'a> {
    let m = 1u32 << layout.depth;
    let f = patch.face;
    let uv = mesh.uv();
    let n = hs.len();
    let vid = |k: usize| mesh.from(hs[k % n]).0;
    let face_uv = uv.map(|fv| {
        let first = mesh.face_lists().0[f.idx()] as usize;
        (0..n).map(|k| fv.corner(first + k)).collect::<Vec<Vec2>>()
    });
    if patch.sub == u32::MAX {
        let p = bilinear_patch_corners(mesh, f, None);
        let t = face_uv.as_ref().map(|t| [t[0], t[1], t[2], t[3]]);
        let (lh, hs4) = (layout, [hs[0], hs[1], hs[2], hs[3]]);
        let corner_ids = [0, 1, 2, 3].map(vid);
        let interior = patch.interior;
        let grid = move |i: u32, j: u32| -> u32 {
            let c = |k: usize| [corner_ids[k], corner_ids[(k + 1) % 4]];
            match (i, j) {
                (_, 0) => lh.on_edge(hs4[0], i, c(0)),
                (i, j) if i == m => lh.on_edge(hs4[1], j, c(1)),
                (i, j) if j == m => lh.on_edge(hs4[2], m - i, c(2)),
                (0, j) => lh.on_edge(hs4[3], m - j, c(3)),
                (i, j) => interior + (j - 1) * (m - 1) + (i - 1),
            }
        };
        PatchGrid {
            c: Corners { p, uv: t },
            side: m,
            ids: Box::new(grid),
        }
    } else {
        let k = patch.sub as usize;
        let m1 = m / 2;
        let (hk, hp) = (hs[k], hs[(k + n - 1) % n]);
        let p = bilinear_patch_corners(mesh, f, Some(k));
        let centroid = p[2];
        let t = face_uv.as_ref().map(|t| {
            let c = t.iter().copied().sum::<Vec2>() / n as f32;
            let (a, b, z) = (t[k], t[(k + 1) % n], t[(k + n - 1) % n]);
            [a, (a + b) * 0.5, c, (z + a) * 0.5]
        });
        let fp = layout.face_point[f.idx()];
        let spokes = layout.spoke_base[f.idx()];
        pos[fp as usize] = centroid.to_array();
        // The points inside the level-1 edge from this quad's edge midpoint to the centre.
        for j in 1..m1 {
            let id = spokes + k as u32 * (m1 - 1) + j - 1;
            pos[id as usize] = lerp(p[1], centroid, j as f32 / m1 as f32).to_array();
        }
        let (lh, vk) = (layout, vid(k));
        let (vn, vp) = (vid(k + 1), vid(k + n - 1));
        let kp = ((k + n - 1) % n) as u32;
        let (interior, kk) = (patch.interior, k as u32);
        let grid = move |i: u32, j: u32| -> u32 {
            match (i, j) {
                (_, 0) => lh.on_edge(hk, i, [vk, vn]),
                (0, j) => lh.on_edge(hp, m - j, [vp, vk]),
                (i, j) if i == m1 && j == m1 => fp,
                (i, j) if i == m1 => spokes + kk * (m1 - 1) + j - 1,
                (i, j) if j == m1 => spokes + kp * (m1 - 1) + i - 1,
                (i, j) => interior + (j - 1) * (m1 - 1) + (i - 1),
            }
        };
        PatchGrid {
            c: Corners { p, uv: t },
            side: m1,
            ids: Box::new(grid),
        }
    }
}
