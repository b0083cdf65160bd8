//! DoI-driven adaptive Loop subdivision (Isenberg, Hartmann & König 2003, §3 and Fig. 1).
//!
//! One step takes a face selection (in the paper, the faces whose Degree of Interest exceeds the
//! threshold; this crate knows nothing of DoIs), and the red-green closure of [`crate::red_green`]
//! decides what is refined. Then, following the paper:
//!
//! - "Vertices that are part of a subdivided triangle are re-positioned according to regular
//!   Loop subdivision. All other vertices remain in their original positions." A vertex moves
//!   when it is a corner of a refined triangle (selected, promoted, or the parent of a merged
//!   green family); its new position is Loop's vertex rule over its one-ring in the current mesh,
//!   with crease and boundary rules exactly as in `subdiv_rules::refine_uniform` (both apply
//!   the one kernel, [`subdiv_rules::RefineKernel`]).
//! - Every split edge gets Loop's edge point (crease-aware). For the edge of a merged family's
//!   parent, the opposite vertex on that side is the parent's opposite corner.
//! - Split edges of sharp (crease) edges pass the decayed sharpness to their halves; edges that
//!   are not split keep theirs, and so do vertices that do not move.
//!
//! With every face selected the step is exactly `subdiv_rules::refine_uniform` (same vertex
//! numbering, faces and bit-identical positions).
//!
//! Triangle quality. Moving vertices by the vertex rule over a one-ring whose neighbours are at
//! different levels (as the paper prescribes) distorts the fine triangles beside long coarse
//! edges, and green bisections halve angles; without care the distortion accumulates: on
//! `tri_bunny_3k` with the view-angle DoI the smallest angle falls from 13.2° to 0.4° in five
//! steps, on the teapot with the silhouette DoI to 0°. [`loop_step`] ([`Balance::Vertex`])
//! therefore keeps three rules of the red-green literature (Bank, Sherman & Weiser):
//!
//! 1. levels are balanced ([`red_green::balance`]): faces sharing a vertex differ by at most one
//!    level, a face with two split edges is refined red;
//! 2. no green bisection cuts a small angle: a triangle whose bisection would make an angle
//!    below the cage's smallest (or, for a fat triangle, worse than an exact bisection of its
//!    own smallest angle) is refined red instead, which propagates;
//! 3. every vertex is read at the level being refined: the step runs one pass per level,
//!    coarsest first (`pass.rs`), each reading every vertex's position at that level (the
//!    current one, or [`AdaptiveMesh::previous`] for a vertex one level ahead) and leaving out
//!    of a vertex's ring the edges inside green families. With 1. every face around a refined
//!    face's corners then has the pass's level, so the vertex and edge points are exactly uniform
//!    Loop's: every vertex sits where uniform Loop puts it at its level (the highest level of the
//!    faces around it), and each is smoothed once per level.
//!
//! Measured (`triangle_quality_*` in `tests/tests/doi.rs`: smallest angle after five steps,
//! seven DoIs): the teapot's lip is a ring of strips 2.8 long and 0.15 wide holding the cage's
//! smallest angle, 3.09° (uniform Loop: 2.72° at levels 1 to 5). Before these rules the
//! view-angle / silhouette / dihedral DoIs ended at 0.98° / 0.00° / 1.41°; with 1. and 3. only,
//! 1.38° / 1.54° / 1.42° (green bisections of the strips' small angles); with 1. and 2. only
//! (2. at three quarters of the cage's angle), 0.05° / 0.20° / 2.26° (mixed-level smoothing
//! moves lip vertices by a strip's width); with all three every DoI stays at or above 1.98°
//! (bound 1.54°), and the bunny at or above 11.1° (bound 6.6°), for 8% more triangles than
//! before on the teapot's view-angle DoI (436 434 against 404 064) and 3% on the bunny's
//! (1 123 340 against 1 094 084; docs/figures.md). [`loop_step_with`] with [`Balance::None`] is the paper's
//! plain closure, the vertex rule over the current mesh.

use glam::{Vec2, Vec3};
use subdiv_mesh::Mesh;

use crate::RedGreenError;
use crate::error::check_len;
use crate::pass::{once_per_level, pass};
use crate::red_green::{self, GreenState};

/// Most triangles an adaptive refinement may produce.
pub const MAX_TRIANGLES: u64 = 1 << 26;

/// A triangle mesh under adaptive refinement: the conforming mesh and which of its triangles are
/// green closures.
#[derive(Clone, Debug)]
pub struct AdaptiveMesh {
    /// The conforming triangle mesh.
    pub mesh: Mesh,
    /// Its green families.
    pub green: GreenState,
    /// Per face: its refinement level (0 in the cage, +1 per red split; green triangles have
    /// their parent's level).
    pub level: Vec<u8>,
    /// Per vertex: its position one level before its current one (a vertex's level is the
    /// highest level of the faces around it); its current position for a vertex that has not
    /// moved since it was made. A balanced step reads it for vertices one level ahead of the
    /// faces it refines.
    pub previous: Vec<Vec3>,
    /// Per value of the mesh's UVs ([`Mesh::uv`]; empty without): the value one level before
    /// its vertex's current one, as [`AdaptiveMesh::previous`] for positions; the value itself
    /// for a value that has not moved since it was made.
    pub previous_uv: Vec<Vec2>,
    /// Per primvar of the mesh ([`Mesh::primvars`]), as [`AdaptiveMesh::previous`] for
    /// positions: a vertex primvar's value one level before at every vertex, a face-varying
    /// one's per value (`width` floats each); empty for the others (`crate::primvars`).
    pub previous_primvars: Vec<Vec<f32>>,
    /// Per primvar of the mesh: a face-varying one's [`subdiv_mesh::Dependence`] per value as
    /// [`subdiv_mesh::FaceVarying::dependence`] for the UVs (empty on the cage, where it
    /// follows from the topology, and for the other kinds).
    pub primvar_dependence: Vec<Vec<subdiv_mesh::Dependence>>,
    /// The cage's smallest angle (radians). A balanced step refines red a triangle whose green
    /// bisection would cut an angle too small for it ([`red_green::balance`]); 0 allows every
    /// bisection.
    pub cage_angle: f32,
}

impl AdaptiveMesh {
    /// Starts adaptive refinement from a triangle mesh (no green faces).
    pub fn new(mesh: Mesh) -> Result<AdaptiveMesh, RedGreenError> {
        mesh.check_triangles()?;
        let green = GreenState::new(mesh.num_faces());
        let level = vec![0; mesh.num_faces()];
        let previous = mesh.positions().to_vec();
        let previous_uv = mesh.uv().map(|fv| fv.values.clone()).unwrap_or_default();
        let previous_primvars = crate::primvars::initial_previous(&mesh);
        let primvar_dependence = vec![Vec::new(); mesh.primvars().len()];
        let cage_angle = mesh
            .faces()
            .map(|f| {
                let v = mesh.face_vertices(f);
                let p = |k: usize| mesh.position(v[k]);
                red_green::smallest_angle(p(0), p(1), p(2))
            })
            .fold(std::f32::consts::PI, f32::min);
        Ok(AdaptiveMesh {
            mesh,
            green,
            level,
            previous,
            previous_uv,
            previous_primvars,
            primvar_dependence,
            cage_angle,
        })
    }
}

/// What one step did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Faces whose DoI exceeded the threshold.
    pub selected: usize,
    /// Faces added to the selection to keep the levels balanced.
    pub balanced: usize,
    /// Faces refined 1-to-4 (selected, merged families' faces, promoted).
    pub refined: usize,
    /// Green families merged back into their parents.
    pub merged: usize,
    /// Triangles after the step.
    pub triangles: usize,
    /// Green triangles after the step.
    pub green: usize,
    /// Seconds spent choosing the selection (filled in by the caller, e.g. DoI evaluation).
    pub select_seconds: f64,
    /// Seconds spent refining (filled in by the caller).
    pub refine_seconds: f64,
}

/// How a step grows the selection before the red-green closure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Balance {
    /// Levels 2:1 balanced across vertices ([`red_green::balance`]): the smallest angle does not
    /// decay with the steps.
    #[default]
    Vertex,
    /// No balancing: only the red-green closure of the paper (Fig. 1); fewest triangles, but
    /// thin triangles appear after several steps.
    None,
}

/// One adaptive Loop step refining the faces flagged in `selected` (one flag per face), balanced
/// ([`Balance::Vertex`]) and closed red-green so the result is conforming. Returns the refined
/// mesh and the step's counts (without timings).
///
/// ```
/// use subdiv_redgreen::{loop_step, loop_step_with, AdaptiveMesh, Balance};
/// use subdiv_mesh::{parse_obj, Mesh};
/// let tet = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")?)?;
/// let a = AdaptiveMesh::new(tet)?;
/// // Refine one face: with the paper's closure it becomes 4, its three neighbours get one split
/// // edge each (2 triangles).
/// let (b, stats) = loop_step_with(&a, &[true, false, false, false], Balance::None)?;
/// assert_eq!((b.mesh.num_faces(), stats.refined), (4 + 3 * 2, 1));
/// assert!(b.mesh.edges().all(|e| !b.mesh.is_boundary_edge(e)));
/// // Balanced, the neighbours are refined red: two because bisecting a leg of their right
/// // angle would make an 18.4° angle, below the cage's smallest (45°), the third because its
/// // three edges are then split.
/// let (b, stats) = loop_step(&a, &[true, false, false, false])?;
/// assert_eq!((b.mesh.num_faces(), stats.refined, stats.balanced), (16, 4, 2));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn loop_step(
    cur: &AdaptiveMesh,
    selected: &[bool],
) -> Result<(AdaptiveMesh, StepStats), RedGreenError> {
    loop_step_with(cur, selected, Balance::Vertex)
}

/// [`loop_step`] with the choice of balancing.
pub fn loop_step_with(
    cur: &AdaptiveMesh,
    selected: &[bool],
    balance: Balance,
) -> Result<(AdaptiveMesh, StepStats), RedGreenError> {
    let mesh = &cur.mesh;
    mesh.check_triangles()?;
    // Refuse before allocating: a step at most quadruples every triangle.
    subdiv_rules::Budget::machine().check(mesh, subdiv_rules::Request::Refine { steps: 1 })?;
    check_len("face levels", cur.level.len(), mesh.num_faces())?;
    check_len(
        "previous positions",
        cur.previous.len(),
        mesh.num_vertices(),
    )?;
    check_len(
        "previous UVs",
        cur.previous_uv.len(),
        mesh.uv().map_or(0, |fv| fv.values.len()),
    )?;
    check_len(
        "previous primvar values",
        cur.previous_primvars.len(),
        mesh.primvars().len(),
    )?;
    let count = |s: &[bool]| s.iter().filter(|&&x| x).count();
    let selected_n = count(selected);
    let mut stats = StepStats {
        selected: selected_n,
        ..Default::default()
    };
    let next = match balance {
        Balance::None => {
            let c = red_green::close(mesh, &cur.green, selected)?;
            stats.refined = count(&c.red_face);
            stats.merged = count(&c.merged);
            pass(cur, &c, None)?.0
        }
        Balance::Vertex => {
            let (grown, plan) =
                red_green::balance(mesh, &cur.green, &cur.level, selected, cur.cage_angle)?;
            stats.balanced = count(&grown) - selected_n;
            by_level(cur, &plan.red_face, &mut stats)?
        }
    };
    stats.triangles = next.mesh.num_faces();
    stats.green = next.green.num_green_faces();
    Ok((next, stats))
}

/// Refines the faces flagged in `plan` (a balanced closure: every face around a refined
/// level-`l` face reaches level `l` in the step) one level at a time, coarsest first, each pass
/// reading the vertices at its level ([`pass`]). Counts refined faces and merged families.
fn by_level(
    cur: &AdaptiveMesh,
    plan: &[bool],
    stats: &mut StepStats,
) -> Result<AdaptiveMesh, RedGreenError> {
    let planned = || cur.mesh.faces().filter(|f| plan[f.idx()]);
    let (Some(lo), Some(hi)) = (
        planned().map(|f| cur.level[f.idx()]).min(),
        planned().map(|f| cur.level[f.idx()]).max(),
    ) else {
        return Ok(cur.clone());
    };
    let mut a = cur.clone();
    // Per face of `a`: the face of `cur` it comes from, and whether it was refined this step.
    let mut origin: Vec<u32> = (0..cur.mesh.num_faces() as u32).collect();
    let mut done = vec![false; cur.mesh.num_faces()];
    let mut sel = Vec::new();
    for l in lo..=hi {
        sel.clear();
        sel.extend(
            a.mesh
                .faces()
                .map(|f| !done[f.idx()] && a.level[f.idx()] == l && plan[origin[f.idx()] as usize]),
        );
        if !sel.contains(&true) {
            continue;
        }
        let mut c = red_green::close(&a.mesh, &a.green, &sel)?;
        once_per_level(&a.mesh, &a.level, &mut c);
        stats.refined += c.red_face.iter().filter(|&&r| r).count();
        stats.merged += c.merged.iter().filter(|&&m| m).count();
        let (b, source) = pass(&a, &c, Some(l))?;
        origin = source.iter().map(|&s| origin[s as usize]).collect();
        done = source
            .iter()
            .map(|&s| done[s as usize] || c.red_face[s as usize])
            .collect();
        a = b;
    }
    Ok(a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{PolygonSoup, VertexId, parse_obj};
    use subdiv_rules::{Scheme, refine_uniform};

    const OCTAHEDRON: &str = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
        f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

    fn open_fan_with_crease() -> Mesh {
        Mesh::from_soup(
            &parse_obj(
                "v 0 0 0\nv 1 0 0.2\nv 0.5 1 0\nv -0.5 1 0.3\nv -1 0 0\nv -0.5 -1 0.1\nv 0.5 -1 0\n\
                 f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 6\nf 1 6 7\nf 1 7 2\nt crease 2/1/0 0 1 1.5\nt crease 2/1/0 0 4 1.5\n",
            )
            .unwrap(),
        )
        .unwrap()
    }

    #[test]
    fn selecting_everything_is_uniform_loop_exactly() {
        for mesh in [
            Mesh::from_soup(&parse_obj(OCTAHEDRON).unwrap()).unwrap(),
            open_fan_with_crease(),
        ] {
            let mut a = AdaptiveMesh::new(mesh.clone()).unwrap();
            let mut u = mesh;
            for _ in 0..3 {
                let all = vec![true; a.mesh.num_faces()];
                a = loop_step(&a, &all).unwrap().0;
                u = refine_uniform(&u, Scheme::Loop).unwrap();
                assert_eq!(a.mesh.positions(), u.positions(), "bit-identical positions");
                assert_eq!(a.mesh.face_lists(), u.face_lists());
                assert_eq!(a.mesh.edge_sharpnesses(), u.edge_sharpnesses());
                assert_eq!(a.mesh.vertex_sharpnesses(), u.vertex_sharpnesses());
                assert_eq!(a.green.num_green_faces(), 0);
            }
        }
    }

    #[test]
    fn selecting_nothing_changes_nothing() {
        let m = Mesh::from_soup(&parse_obj(OCTAHEDRON).unwrap()).unwrap();
        let a = AdaptiveMesh::new(m.clone()).unwrap();
        let (b, st) = loop_step(&a, &[false; 8]).unwrap();
        assert_eq!(b.mesh.positions(), m.positions());
        assert_eq!(b.mesh.face_lists(), m.face_lists());
        assert_eq!((st.refined, st.triangles), (0, 8));
    }

    #[test]
    fn random_selections_stay_conforming() {
        let mut a =
            AdaptiveMesh::new(Mesh::from_soup(&parse_obj(OCTAHEDRON).unwrap()).unwrap()).unwrap();
        let mut seed = 0x9e3779b9u32;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed
        };
        for step in 0..6 {
            let sel: Vec<bool> = (0..a.mesh.num_faces()).map(|_| rnd() % 4 == 0).collect();
            let (b, st) = loop_step(&a, &sel).unwrap();
            let m = &b.mesh;
            assert!(
                m.edges().all(|e| !m.is_boundary_edge(e)),
                "step {step}: crack"
            );
            let euler = m.num_vertices() as i64 - m.num_edges() as i64 + m.num_faces() as i64;
            assert_eq!(euler, 2, "step {step}");
            assert!(st.triangles >= a.mesh.num_faces());
            // Vertices not touched by a refined triangle keep their positions.
            a = b;
        }
        assert!(a.green.num_green_faces() > 0);
    }

    /// Largest level difference between faces sharing a vertex.
    fn level_spread(a: &AdaptiveMesh) -> u8 {
        let m = &a.mesh;
        let (mut lo, mut hi) = (vec![u8::MAX; m.num_vertices()], vec![0u8; m.num_vertices()]);
        for f in m.faces() {
            for v in m.face_vertices(f) {
                lo[v.idx()] = lo[v.idx()].min(a.level[f.idx()]);
                hi[v.idx()] = hi[v.idx()].max(a.level[f.idx()]);
            }
        }
        lo.iter().zip(&hi).map(|(l, h)| h - l).max().unwrap_or(0)
    }

    #[test]
    fn balanced_steps_keep_levels_within_one_around_every_vertex() {
        let oct = Mesh::from_soup(&parse_obj(OCTAHEDRON).unwrap()).unwrap();
        for balance in [Balance::Vertex, Balance::None] {
            let mut a = AdaptiveMesh::new(oct.clone()).unwrap();
            // Always refine the face nearest (1, 0.2, 0.1): a deep, local refinement.
            let target = Vec3::new(1.0, 0.2, 0.1);
            let mut added = 0;
            for _ in 0..5 {
                let near = a
                    .mesh
                    .faces()
                    .min_by(|&f, &g| {
                        let d = |x| a.mesh.face_centroid(x).distance(target);
                        d(f).total_cmp(&d(g))
                    })
                    .unwrap();
                let sel: Vec<bool> = a.mesh.faces().map(|f| f == near).collect();
                let (b, st) = loop_step_with(&a, &sel, balance).unwrap();
                added += st.balanced;
                a = b;
                assert_eq!(a.level.len(), a.mesh.num_faces());
            }
            let max_level = *a.level.iter().max().unwrap();
            assert_eq!(max_level, 5, "{balance:?}");
            if balance == Balance::Vertex {
                assert!(level_spread(&a) <= 1, "balanced");
                assert!(added > 0);
                assert!(a.green.families.iter().all(|g| g.num_splits() == 1));
            } else {
                assert!(level_spread(&a) >= 2, "the plain closure leaves jumps");
                assert_eq!(added, 0);
            }
        }
    }

    #[test]
    fn vertices_sit_at_their_uniform_positions() {
        // Balanced steps read every vertex at the level being refined, so each cage vertex sits
        // exactly where uniform Loop puts it at its level (the highest level around it).
        let ico = icosahedron_perturbed();
        for mesh in [ico, open_fan_with_crease()] {
            let mut uniform = vec![mesh.clone()];
            for l in 0..4 {
                uniform.push(refine_uniform(&uniform[l], Scheme::Loop).unwrap());
            }
            let mut a = AdaptiveMesh::new(mesh.clone()).unwrap();
            let target = mesh.position(VertexId(1)) * 1.1 + Vec3::new(0.0, 0.05, 0.02);
            for _ in 0..4 {
                let sel: Vec<bool> = a
                    .mesh
                    .faces()
                    .map(|f| a.mesh.face_centroid(f).distance(target) < 0.9)
                    .collect();
                a = loop_step(&a, &sel).unwrap().0;
            }
            let top = crate::pass::vertex_levels(&a.mesh, &a.level);
            let mut levels = [0; 5];
            for v in mesh.vertices() {
                let l = top[v.idx()] as usize;
                levels[l] += 1;
                let want = uniform[l].positions()[v.idx()];
                let got = a.mesh.positions()[v.idx()];
                assert!(
                    got.distance(want) < 1e-5,
                    "vertex {v:?} level {l}: {got} != {want}"
                );
            }
            assert!(
                levels[0] + levels[1] > 0 && levels[3] + levels[4] > 0,
                "{levels:?}"
            );
        }
    }

    /// An icosahedron with its vertices moved off the sphere (irregular triangles).
    fn icosahedron_perturbed() -> Mesh {
        let t = (1.0 + 5f32.sqrt()) / 2.0;
        let mut p = vec![
            Vec3::new(-1.0, t, 0.0),
            Vec3::new(1.0, t, 0.0),
            Vec3::new(-1.0, -t, 0.0),
            Vec3::new(1.0, -t, 0.0),
            Vec3::new(0.0, -1.0, t),
            Vec3::new(0.0, 1.0, t),
            Vec3::new(0.0, -1.0, -t),
            Vec3::new(0.0, 1.0, -t),
            Vec3::new(t, 0.0, -1.0),
            Vec3::new(t, 0.0, 1.0),
            Vec3::new(-t, 0.0, -1.0),
            Vec3::new(-t, 0.0, 1.0),
        ];
        for (i, q) in p.iter_mut().enumerate() {
            *q *= 0.5 + 0.07 * (i % 5) as f32;
        }
        let f: [[u32; 3]; 20] = [
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        Mesh::from_soup(&PolygonSoup::from_faces(p, &f)).unwrap()
    }

    #[test]
    fn unmoved_vertices_keep_positions_and_moved_ones_follow_loop() {
        let m = Mesh::from_soup(&parse_obj(OCTAHEDRON).unwrap()).unwrap();
        let a = AdaptiveMesh::new(m.clone()).unwrap();
        // Face 0 = (0, 2, 4): those three move; 1, 3 and 5 stay.
        let mut sel = vec![false; 8];
        sel[0] = true;
        let (b, _) = loop_step(&a, &sel).unwrap();
        let u = refine_uniform(&m, Scheme::Loop).unwrap();
        for v in [0usize, 2, 4] {
            assert_eq!(b.mesh.positions()[v], u.positions()[v]);
        }
        for v in [1usize, 3, 5] {
            assert_eq!(b.mesh.positions()[v], m.positions()[v]);
        }
    }

    #[test]
    fn bad_input() {
        let quad =
            Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap())
                .unwrap();
        let e = AdaptiveMesh::new(quad).unwrap_err();
        assert!(matches!(
            e,
            RedGreenError::Mesh(subdiv_mesh::MeshError::NotTriangles { face: 0, size: 4 })
        ));
        assert!(e.to_string().contains("face 0 has 4 vertices"));
        let a =
            AdaptiveMesh::new(Mesh::from_soup(&parse_obj(OCTAHEDRON).unwrap()).unwrap()).unwrap();
        let e = loop_step(&a, &[true]).unwrap_err();
        assert!(
            e.to_string()
                .contains("selection has 1 entries but the mesh has 8"),
            "{e}"
        );
    }
}
