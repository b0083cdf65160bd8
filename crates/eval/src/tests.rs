//! Unit tests: lattice points against `subdiv-rules`' exact vertex limits, derivatives against
//! differences, continuity across edges, batches against single points, UVs against the
//! face-varying limits, errors.

use glam::DVec3;
use subdiv_mesh::{FaceId, Mesh, VertexId, parse_obj, read_obj};
use subdiv_rules::{
    Ring, Scheme, limit_face_varying, refine_uniform_levels, refine_uniform_levels_f64,
    semi_sharp_levels,
};
use subdiv_test_support::{Rng, fixture_files, shape};

use super::*;

/// The reference shapes and their schemes.
fn shapes() -> Vec<(String, Mesh, Scheme)> {
    let mut out = Vec::new();
    for path in fixture_files("reference/shapes", "obj") {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let scheme = if name.starts_with("loop") {
            Scheme::Loop
        } else {
            Scheme::CatmullClark
        };
        out.push((name, read_obj(&path).unwrap(), scheme));
    }
    assert!(out.len() >= 30, "{} shapes", out.len());
    out
}

/// The other fixture cages small enough for the lattice test (non-manifold, fuzz finds,
/// boundary `none`, Loop slates), with the scheme of their OpenSubdiv reference.
fn other_cages() -> Vec<(String, Mesh, Scheme)> {
    let mut out = Vec::new();
    for dir in [
        "nonmanifold",
        "osd_fuzz",
        "boundary_none",
        "loop_slate",
        "osd_watertight",
    ] {
        for path in fixture_files(dir, "obj") {
            let name = path.file_stem().unwrap().to_string_lossy().to_string();
            let header = ["L1", "L2", "L3", "L4"]
                .iter()
                .find_map(|l| {
                    std::fs::read_to_string(path.with_file_name(format!("{name}.{l}.txt"))).ok()
                })
                .unwrap_or_default();
            let text = std::fs::read_to_string(&path).unwrap();
            let scheme = if header.lines().next().unwrap_or("").contains("scheme=loop")
                || (header.is_empty() && text.contains("scheme loop"))
            {
                Scheme::Loop
            } else {
                Scheme::CatmullClark
            };
            let cage = subdiv_mesh::read_cage(&path, &Default::default()).unwrap();
            out.push((format!("{dir}/{name}"), cage.mesh, scheme));
        }
    }
    out
}

fn diagonal(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounds();
    (hi - lo).length() as f64
}

/// The exact limit and the one-sided normal of `face`'s side of vertex `v` of a refined mesh
/// with `f64` positions `pos`: the ring's limit, refined on while a level moves it (darts,
/// valence 2: OpenSubdiv's masks are not their limit).
fn vertex_limit(
    m: &Mesh,
    pos: &[DVec3],
    v: VertexId,
    face: FaceId,
    scheme: Scheme,
) -> (DVec3, Option<DVec3>) {
    let mut ring = Ring::new();
    let hs: Vec<_> = m.outgoing(v).collect();
    let origin = pos[v.idx()];
    ring.load_at(m, |w| pos[w.idx()] - origin, v, scheme);
    let fi = hs.iter().position(|&h| m.face(h) == face).unwrap();
    // A copy of a non-manifold vertex takes another copy's limit normal (`Ring::limit`); a
    // corner with fewer than two sharp edges is a cone point, without a tangent plane.
    let sharp = ring
        .edge_sharpnesses()
        .iter()
        .filter(|&&s| s >= 10.0)
        .count();
    let cone = ring.vertex_sharpness() >= 10.0 && sharp < 2;
    let copy = ring.has_master() || !ring.whole().is_empty() || cone;
    let mut sided = Vec::new();
    let mut at = |r: &mut Ring| {
        let (p, n) = r.limit_sided(&mut sided);
        (p, sided.get(fi).copied().unwrap_or(n))
    };
    let (mut p, mut n) = at(&mut ring);
    // Moved to its own centre at every level (its points converge on the limit, and about
    // another point they would lose their relative precision within some 50 levels).
    let mut origin = origin;
    for _ in 0..120 {
        ring.refine();
        let shift = ring.center();
        ring.translate(-shift);
        origin += shift;
        let (q, k) = at(&mut ring);
        let still = (q + shift - p).length() < 1e-15 && (k - n).length() < 1e-13;
        (p, n) = (q, k);
        if still {
            return (p + origin, (!copy).then_some(n));
        }
    }
    (p + origin, None)
}

/// At the corners of the level-2 faces, the evaluation is the exact vertex limit and its
/// one-sided normal, on every reference shape (creases, corners, boundaries, n-gons, darts,
/// valence 2, Chaikin, holes, both schemes). The reference is the vertex's ring refined until
/// its limit masks stop moving (they move at darts, valence 2 and irregular crease sectors).
#[test]
fn lattice_points_are_the_exact_vertex_limits() {
    let depth = 2;
    let mut bad = Vec::new();
    let mut checked = 0;
    for (name, mesh, scheme) in shapes().into_iter().chain(other_cages()) {
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let (refined, pos) = refine_uniform_levels_f64(&mesh, scheme, depth).unwrap();
        let diag = diagonal(&mesh);
        let faces = refined_faces(&mesh, scheme, depth);
        assert_eq!(faces.len(), refined.num_faces(), "{name}");
        let mut surface = FaceSurface::new();
        for (f, (face, params)) in faces.iter().enumerate() {
            if mesh.is_hole(FaceId(*face)) {
                continue;
            }
            eval.load_surface(*face, &mut surface).unwrap();
            let verts = refined.face_vertices(FaceId(f as u32));
            for (k, p) in params.iter().enumerate() {
                let s = surface.evaluate(p[0], p[1], Derivatives::First).unwrap();
                let (want, normal) =
                    vertex_limit(&refined, &pos, verts[k], FaceId(f as u32), scheme);
                let d = (s.position - want).length();
                if d > 1e-9 * diag {
                    let at = format!("{name}: face {face} at {p:?}");
                    bad.push(format!("{at}: {} vs {want} ({d})", s.position));
                }
                if let Some(normal) = normal.filter(|n| *n != DVec3::ZERO)
                    && s.normal() != DVec3::ZERO
                {
                    let angle = s.normal().angle_between(normal).to_degrees();
                    if angle > 1e-5 {
                        bad.push(format!(
                            "{name}: face {face} at {p:?}: normal off by {angle} deg"
                        ));
                    }
                }
                checked += 1;
            }
        }
    }
    assert!(
        bad.is_empty(),
        "{} points differ, first: {:#?}",
        bad.len(),
        &bad[..bad.len().min(10)]
    );
    assert!(checked > 50_000, "{checked}");
}

/// Random points: first and second derivatives are those of the positions (central
/// differences), on shapes with creases, semi-sharpness, n-gons and both schemes.
#[test]
fn derivatives_are_the_differences_of_positions() {
    let names = [
        "catmark_torus_creases0",
        "catmark_cube_creases1",
        "catmark_nonquads",
        "catmark_chaikin0",
        "catmark_edgecorner",
        "loop_cubes_semisharp",
        "loop_saddle_edgecorner",
        "loop_icosahedron",
    ];
    let mut rng = Rng::splitmix(7);
    for name in names {
        let scheme = if name.starts_with("loop") {
            Scheme::Loop
        } else {
            Scheme::CatmullClark
        };
        let mesh = read_obj(shape(&format!("{name}.obj"))).unwrap();
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let diag = diagonal(&mesh);
        for _ in 0..60 {
            let face = rng.below(mesh.num_faces()) as u32;
            let Ok(domain) = eval.domain(face) else {
                continue;
            };
            let [u, v] = random_point(&domain, &mut rng, 0.02);
            let at = |u: f64, v: f64| {
                eval.evaluate(Query::new(face, u, v), Derivatives::Second)
                    .unwrap()
            };
            let s = at(u, v);
            let h = 1e-5;
            let (pu, mu, pv, mv) = (at(u + h, v), at(u - h, v), at(u, v + h), at(u, v - h));
            let fd = |a: DVec3, b: DVec3| (a - b) / (2.0 * h);
            let scale = diag * 4.0;
            let close =
                |a: DVec3, b: DVec3, tol: f64| (a - b).length() <= tol * scale.max(b.length());
            assert!(
                close(fd(pu.position, mu.position), s.du, 1e-6),
                "{name} {face} ({u}, {v}) du"
            );
            assert!(
                close(fd(pv.position, mv.position), s.dv, 1e-6),
                "{name} {face} ({u}, {v}) dv"
            );
            assert!(
                close(fd(pu.du, mu.du), s.duu, 1e-4),
                "{name} {face} ({u}, {v}) duu"
            );
            assert!(
                close(fd(pv.du, mv.du), s.duv, 1e-4),
                "{name} {face} ({u}, {v}) duv"
            );
            assert!(
                close(fd(pv.dv, mv.dv), s.dvv, 1e-4),
                "{name} {face} ({u}, {v}) dvv"
            );
        }
    }
}

/// A random point of `domain` at least `margin` inside its tiles (or triangle).
fn random_point(domain: &Domain, rng: &mut Rng, margin: f64) -> [f64; 2] {
    let mut r = || margin + (1.0 - 2.0 * margin) * rng.next_f64();
    match *domain {
        Domain::Quad => [r(), r()],
        Domain::Triangle => loop {
            let (u, v) = (r(), r());
            if u + v <= 1.0 - margin {
                break [u, v];
            }
        },
        Domain::SubFaces { corners, .. } => {
            let k = (r() * f64::from(corners)) as usize % corners as usize;
            let [x, y] = domain.corner(k);
            [x + 0.5 * r(), y + 0.5 * r()]
        }
    }
}

/// Points on a cage edge agree from both faces (the surface is continuous, and both sides
/// refine their own neighbourhoods to the same bits up to rounding).
#[test]
fn shared_edges_agree_from_both_sides() {
    let mut rng = Rng::splitmix(3);
    for (name, mesh, scheme) in shapes() {
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let diag = diagonal(&mesh);
        for f in mesh.faces() {
            let Ok(domain) = eval.domain(f.0) else {
                continue;
            };
            let mut h = mesh.face_halfedge(f);
            for k in 0..mesh.face_size(f) {
                let g = mesh.face(h.twin());
                if g.is_some() && eval.domain(g.0).is_ok() {
                    let gd = eval.domain(g.0).unwrap();
                    let gk = mesh
                        .face_vertices(g)
                        .iter()
                        .position(|&w| w == mesh.to(h))
                        .unwrap();
                    let t = rng.next_f64();
                    let a = domain.edge_point(k, t);
                    let b = gd.edge_point(gk, 1.0 - t);
                    let pa = eval
                        .evaluate(Query::new(f.0, a[0], a[1]), Derivatives::First)
                        .unwrap();
                    let pb = eval
                        .evaluate(Query::new(g.0, b[0], b[1]), Derivatives::First)
                        .unwrap();
                    let d = (pa.position - pb.position).length();
                    assert!(
                        d <= 1e-11 * diag,
                        "{name}: faces {f:?} {g:?} edge {k} t {t}: {d}"
                    );
                }
                h = mesh.next(h);
            }
        }
    }
}

/// The parallel batch gives exactly what single points give, in any query order.
#[test]
fn batches_equal_single_points() {
    let mesh = read_obj(shape("catmark_pawn.obj")).unwrap();
    let eval = Evaluator::new(&mesh, Scheme::CatmullClark).unwrap();
    let mut rng = Rng::splitmix(11);
    let queries: Vec<Query> = (0..2000)
        .map(|_| {
            let face = rng.below(mesh.num_faces()) as u32;
            let [u, v] = random_point(&eval.domain(face).unwrap(), &mut rng, 0.0);
            Query::new(face, u, v)
        })
        .collect();
    let mut out = vec![Sample::default(); queries.len()];
    eval.evaluate_many(&queries, Derivatives::Second, &mut out)
        .unwrap();
    for (q, s) in queries.iter().zip(&out) {
        assert_eq!(*s, eval.evaluate(*q, Derivatives::Second).unwrap());
    }
}

/// UVs at the lattice are the face-varying limits of the refined cage (OpenSubdiv's
/// `LimitFaceVarying`, which `subdiv-rules` reproduces), for every face-varying option.
#[test]
fn uvs_at_the_lattice_are_the_face_varying_limits() {
    let mut checked = 0;
    for path in fixture_files("meshes/fvar", "obj") {
        let text = std::fs::read_to_string(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        for (option, scheme) in (0..6).flat_map(|o| [(o, Scheme::CatmullClark), (o, Scheme::Loop)])
        {
            let text = format!("{text}\nt facevaryinginterpolateboundary 1/0/0 {option}\n");
            let mut soup = parse_obj(&text).unwrap();
            soup.split_nonmanifold().unwrap();
            let mesh = Mesh::from_soup(&soup).unwrap();
            let Ok(eval) = Evaluator::new(&mesh, scheme) else {
                continue;
            };
            // Deep enough that no semi-sharp feature is left: before that OpenSubdiv's limit
            // keeps semi-sharp values in place, where the evaluation is the true limit.
            let depth = semi_sharp_levels(&mesh).max(2);
            let refined = refine_uniform_levels(&mesh, scheme, depth).unwrap();
            let lim = limit_face_varying(&refined, scheme).unwrap();
            let (offsets, _) = refined.face_lists();
            for (f, (face, params)) in refined_faces(&mesh, scheme, depth).iter().enumerate() {
                for (k, p) in params.iter().enumerate() {
                    let uv = eval
                        .evaluate_uv(Query::new(*face, p[0], p[1]))
                        .unwrap()
                        .unwrap();
                    let want = lim.corner(offsets[f] as usize + k).as_dvec2();
                    let d = (uv.uv - want).length();
                    assert!(
                        d < 1e-5,
                        "{name} {scheme:?} option {option}: face {face} at {p:?}: {} vs {want}",
                        uv.uv
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}

/// Bad queries give typed errors naming the face.
#[test]
fn errors_name_the_face() {
    let text = subdiv_test_support::cube().obj() + "t hole 1/0/0 2\n";
    let mesh = Mesh::from_soup(&parse_obj(&text).unwrap()).unwrap();
    let eval = Evaluator::new(&mesh, Scheme::CatmullClark).unwrap();
    let e = eval
        .evaluate(Query::new(6, 0.5, 0.5), Derivatives::First)
        .unwrap_err();
    assert!(
        matches!(e, EvalError::FaceOutOfRange { face: 6, faces: 6 }),
        "{e}"
    );
    let e = eval
        .evaluate(Query::new(2, 0.5, 0.5), Derivatives::First)
        .unwrap_err();
    assert!(matches!(e, EvalError::Hole { face: 2 }), "{e}");
    let e = eval
        .evaluate(Query::new(1, 0.5, -0.1), Derivatives::First)
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("outside face 1's domain, the unit square"),
        "{e}"
    );
    let mut out = vec![Sample::default(); 2];
    let qs = [Query::new(0, 0.1, 0.1), Query::new(0, f64::NAN, 0.0)];
    assert!(
        eval.evaluate_many(&qs, Derivatives::First, &mut out)
            .is_err()
    );
    assert_eq!(out[0], Sample::default());
    let e = Evaluator::new(&mesh, Scheme::Loop).unwrap_err();
    assert!(e.to_string().contains("face 0 has 4 vertices"), "{e}");
}

/// The fast path of fully regular faces is the ring path, to the bit.
#[test]
fn regular_faces_fast_path_is_the_ring_path() {
    let mut regular = 0;
    for (name, mesh, scheme) in shapes() {
        let plans = crate::plan::regular_plans(&mesh, scheme);
        let mut rng = Rng::splitmix(5);
        for f in mesh.faces() {
            let Some(plan) = plans[f.idx()].as_ref() else {
                continue;
            };
            regular += 1;
            let (mut a, mut b) = (FaceSurface::new(), FaceSurface::new());
            a.load(&mesh, scheme, f, Some(plan));
            b.load(&mesh, scheme, f, None);
            let [u, v] = random_point(&a.domain(), &mut rng, 0.0);
            let sa = a.evaluate(u, v, Derivatives::Second).unwrap();
            let sb = b.evaluate(u, v, Derivatives::Second).unwrap();
            assert_eq!(sa, sb, "{name} face {f:?}");
        }
    }
    assert!(regular > 300, "{regular}");
}
