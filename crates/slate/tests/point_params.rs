//! Each output point's parameter point (`UniformTessellator::point_params`,
//! `PatchLayout::point_params`, `TriLayout::point_params`) names where the point lies on the limit
//! surface: the exact evaluation there (`subdiv_eval`, OpenSubdiv's `Bfr` parameterisation) is
//! the slate's limit point and normal. The slates agree with OpenSubdiv to about 1e-6 of the
//! cage's size, so a wrong face, a turned or mirrored domain or a wrong tile is far beyond the
//! tolerances here. Cages with holes, seams or isolated vertices have none.
//!
//! As in `subdiv-tests`' `eval_lattice`: the slates take OpenSubdiv's limit masks at the
//! tessellation's level, and where those move with the level (crease and corner sectors that are
//! not a regular half-plane, darts, valence 2) the evaluation is the limit instead. At a cage
//! vertex the test checks exactly that: the slate point is the level-`d` masks' and the masks a
//! few levels deeper differ.

use std::path::PathBuf;

use glam::DVec3;
use subdiv_eval::{Derivatives, Evaluator, Query, Sample};
use subdiv_mesh::{FaceId, VertexId};
use subdiv_mesh::{Mesh, read_obj};
use subdiv_rules::{Ring, Scheme, SeamCurves, VertexParams};
use subdiv_slate::{PatchLayout, TriLayout, UniformTessellator};

/// Positions within this times the cage's bounding-box diagonal.
const POSITION_TOLERANCE: f64 = 1e-4;
/// Normals within this many radians.
const NORMAL_TOLERANCE: f64 = 1e-3;

const CAGES: [(&str, Scheme); 10] = [
    ("reference/shapes/catmark_pawn.obj", Scheme::CatmullClark),
    ("reference/shapes/catmark_helmet.obj", Scheme::CatmullClark),
    (
        "reference/shapes/catmark_nonquads.obj",
        Scheme::CatmullClark,
    ),
    ("reference/shapes/catmark_triquad.obj", Scheme::CatmullClark),
    ("reference/shapes/catmark_pole8.obj", Scheme::CatmullClark),
    (
        "reference/shapes/catmark_torus_creases0.obj",
        Scheme::CatmullClark,
    ),
    ("reference/shapes/loop_cube_creases0.obj", Scheme::Loop),
    ("reference/shapes/loop_pole8.obj", Scheme::Loop),
    ("reference/shapes/loop_cubes_semisharp.obj", Scheme::Loop),
    ("meshes/cc_3torus.obj", Scheme::CatmullClark),
];

fn cage(rel: &str) -> Mesh {
    let path: PathBuf = subdiv_test_support::fixture(rel);
    read_obj(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn angle(a: DVec3, b: DVec3) -> f64 {
    a.dot(b).clamp(-1.0, 1.0).acos()
}

/// At cage vertex `v` of `mesh`, the masks' limit after `depth` levels and `extra` levels
/// deeper, each with the one-sided normal of `face`'s side where there is one.
fn masks(mesh: &Mesh, v: VertexId, face: FaceId, scheme: Scheme, depth: u8) -> [(DVec3, DVec3); 2] {
    let fi = mesh
        .outgoing(v)
        .position(|h| mesh.face(h) == face)
        .unwrap_or(0);
    let mut ring = Ring::new();
    ring.load(mesh, v, scheme);
    for _ in 0..depth {
        ring.refine();
    }
    let mut sided = Vec::new();
    let mut at = |r: &mut Ring| {
        let (p, n) = r.limit_sided(&mut sided);
        (p, sided.get(fi).copied().unwrap_or(n))
    };
    let first = at(&mut ring.clone());
    for _ in 0..8 {
        ring.refine();
    }
    [first, at(&mut ring)]
}

/// The layout's own parameter points, which the tessellator's must be.
fn layout_params(mesh: &Mesh, scheme: Scheme, depth: u8) -> Option<VertexParams> {
    match scheme {
        Scheme::Loop => TriLayout::new(mesh, depth).unwrap().point_params(mesh),
        _ => PatchLayout::new(mesh, depth).unwrap().point_params(mesh),
    }
}

/// The points of `rel` at `depth` whose evaluation at their parameter point is not the slate's
/// limit point and normal, described; and how many points were checked.
/// Also counts, in `moving`, the cage vertices where the masks move with the level.
fn mismatches(
    rel: &str,
    scheme: Scheme,
    depth: u8,
    moving: &mut Vec<String>,
) -> (Vec<String>, usize) {
    let mesh = cage(rel);
    let t = UniformTessellator::new(&mesh, scheme, depth).unwrap();
    let params = t
        .point_params()
        .unwrap_or_else(|| panic!("{rel} depth {depth}: no parameter points"));
    assert_eq!(
        Some(&params),
        layout_params(&mesh, scheme, depth).as_ref(),
        "{rel} depth {depth}: the tessellator's are the layout's"
    );
    let surface = t.surface();
    let n = surface.positions().len();
    assert_eq!(
        params.face.len(),
        n,
        "{rel} depth {depth}: one face a point"
    );
    assert_eq!(
        params.uv.len(),
        n,
        "{rel} depth {depth}: one (u, v) a point"
    );

    let queries: Vec<Query> = (0..n)
        .map(|i| {
            let [u, v] = params.uv[i];
            Query::new(params.face[i], f64::from(u), f64::from(v))
        })
        .collect();
    let eval = Evaluator::new(&mesh, scheme).unwrap();
    let mut samples = vec![Sample::default(); n];
    eval.evaluate_many(&queries, Derivatives::First, &mut samples)
        .unwrap_or_else(|e| panic!("{rel} depth {depth}: {e}"));

    // The one-sided normals at each point (creases and corners), any of which the evaluation
    // of one face's side may be.
    let mut sided: Vec<Vec<DVec3>> = vec![Vec::new(); n];
    for &(c, nrm) in surface.corner_normals() {
        let v = surface.face_indices()[c as usize] as usize;
        sided[v].push(glam::Vec3::from(nrm).as_dvec3());
    }
    let (lo, hi) = mesh
        .positions()
        .iter()
        .fold((DVec3::MAX, DVec3::MIN), |(lo, hi), p| {
            (lo.min(p.as_dvec3()), hi.max(p.as_dvec3()))
        });
    let tolerance = POSITION_TOLERANCE * (hi - lo).length();

    let mut bad = Vec::new();
    for (i, s) in samples.iter().enumerate() {
        let q = queries[i];
        let p = glam::Vec3::from(surface.positions()[i]).as_dvec3();
        let d = (s.position - p).length();
        if d > tolerance {
            bad.push(format!(
                "{rel} depth {depth} point {i} at face {} ({}, {}): position off by {d:.3e} (tolerance {tolerance:.3e})",
                q.face, q.u, q.v
            ));
            continue;
        }
        let (mine, theirs) = (
            glam::Vec3::from(surface.normals()[i]).as_dvec3(),
            s.normal(),
        );
        if mine == DVec3::ZERO || theirs == DVec3::ZERO {
            continue;
        }
        let nearest = |to: DVec3| {
            sided[i]
                .iter()
                .map(|&o| angle(o, to))
                .fold(angle(mine, to), f64::min)
        };
        let best = nearest(theirs);
        if best > NORMAL_TOLERANCE && i < mesh.num_vertices() {
            // The masks move at this cage vertex: the slate's point is theirs at level `depth`,
            // the evaluation the limit.
            let v = VertexId(i as u32);
            let [(p0, n0), (p1, n1)] = masks(&mesh, v, FaceId(q.face), scheme, depth);
            let moved = (p1 - p0).length() > 1e-9 * tolerance || angle(n0, n1) > NORMAL_TOLERANCE;
            let slate_is_masks = (p0 - p).length() <= tolerance && nearest(n0) <= NORMAL_TOLERANCE;
            if moved && slate_is_masks {
                moving.push(format!("{rel} depth {depth} vertex {i}: {best:.3e} rad"));
                continue;
            }
        }
        if best > NORMAL_TOLERANCE {
            bad.push(format!(
                "{rel} depth {depth} point {i} at face {} ({}, {}): normal off by {best:.3e} rad",
                q.face, q.u, q.v
            ));
        }
    }
    (bad, n)
}

#[test]
fn the_evaluation_at_each_parameter_point_is_the_slate_point() {
    let (mut bad, mut moving) = (Vec::new(), Vec::new());
    for (rel, scheme) in CAGES {
        for depth in 1..=3 {
            let (b, n) = mismatches(rel, scheme, depth, &mut moving);
            assert!(n > 0);
            bad.extend(b);
        }
    }
    println!(
        "{} cage vertices where the masks move with the level:\n{}",
        moving.len(),
        moving.join("\n")
    );
    assert!(
        bad.is_empty(),
        "{} points off:\n{}",
        bad.len(),
        bad[..bad.len().min(40)].join("\n")
    );
}

/// Every parameter point lies in its face's domain, and the face corners (the cage vertices)
/// sit at their faces' domain corners.
#[test]
fn the_parameter_points_are_in_their_domains() {
    for (rel, scheme) in CAGES {
        let mesh = cage(rel);
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let params = layout_params(&mesh, scheme, 2).unwrap();
        for (i, (&f, &[u, v])) in params.face.iter().zip(&params.uv).enumerate() {
            let q = Query::new(f, f64::from(u), f64::from(v));
            assert!(eval.locate(q).is_ok(), "{rel}: point {i} at {q:?}");
            if i < mesh.num_vertices() {
                let domain = eval.domain(f).unwrap();
                let k = mesh
                    .face_vertices(subdiv_mesh::FaceId(f))
                    .iter()
                    .position(|x| x.idx() == i)
                    .unwrap_or_else(|| panic!("{rel}: vertex {i} not in its face {f}"));
                let corner = domain.corner(k).map(|x| x as f32);
                assert_eq!(
                    [u, v],
                    corner,
                    "{rel}: vertex {i} at corner {k} of face {f}"
                );
            }
        }
    }
}

#[test]
fn holes_seams_and_isolated_vertices_have_no_parameter_points() {
    // A hole: its hidden patch.
    for (rel, scheme) in [
        ("reference/shapes/catmark_pawn.obj", Scheme::CatmullClark),
        (
            "reference/shapes/catmark_nonquads.obj",
            Scheme::CatmullClark,
        ),
        ("reference/shapes/loop_pole8.obj", Scheme::Loop),
    ] {
        let mut mesh = cage(rel);
        let mut holes = vec![false; mesh.num_faces()];
        holes[1] = true;
        mesh.set_holes(holes);
        for depth in 1..=2 {
            assert_eq!(
                layout_params(&mesh, scheme, depth),
                None,
                "{rel} with a hole"
            );
            let t = UniformTessellator::new(&mesh, scheme, depth).unwrap();
            assert_eq!(t.point_params(), None, "{rel} with a hole");
        }
    }
    // An isolated vertex.
    let quads =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 5 5 5\nf 1 2 3 4\nf 2 5 6 3\n";
    let tris = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 5 5 5\nf 1 2 3\nf 2 4 3\n";
    for (text, scheme) in [(quads, Scheme::CatmullClark), (tris, Scheme::Loop)] {
        let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(text).unwrap()).unwrap();
        assert_eq!(layout_params(&mesh, scheme, 2), None, "{scheme:?} isolated");
        // Without the isolated vertex the same cage has them.
        let text = text.replace("v 5 5 5\n", "");
        let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(&text).unwrap()).unwrap();
        assert!(
            layout_params(&mesh, scheme, 2).is_some(),
            "{scheme:?} connected"
        );
    }
    // Seams: the copies of non-manifold edges.
    let mut seams = 0;
    for path in subdiv_test_support::fixture_files("nonmanifold", "obj") {
        let Ok(mesh) = read_obj(&path) else { continue };
        if SeamCurves::new(&mesh).groups().is_empty() {
            continue;
        }
        seams += 1;
        assert_eq!(
            layout_params(&mesh, Scheme::CatmullClark, 2),
            None,
            "{}",
            path.display()
        );
    }
    assert!(seams > 0, "no fixture with seams");
    // Neither the bilinear scheme nor depth 0 has a slate layout.
    let mesh = cage("reference/shapes/catmark_pawn.obj");
    for (scheme, depth) in [(Scheme::Bilinear, 2), (Scheme::CatmullClark, 0)] {
        let t = UniformTessellator::new(&mesh, scheme, depth).unwrap();
        assert_eq!(t.point_params(), None, "{scheme:?} depth {depth}");
    }
}
