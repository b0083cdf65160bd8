//! The bilinear scheme measured against its refinement: at the lattice of `subdiv-rules`'
//! uniform bilinear refinement (which agrees with OpenSubdiv's, `tests/tests/reference.rs`)
//! the evaluation is the refined vertex, and its UVs the refined face-varying values;
//! derivatives are the differences of positions.

use glam::DVec3;
use subdiv_mesh::{FaceId, Mesh, parse_obj, read_obj};
use subdiv_rules::{Scheme, refine_uniform_levels, refine_uniform_levels_f64};
use subdiv_test_support::{Rng, fixture_files, shape};

use super::*;

fn diagonal(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounds();
    f64::from((hi - lo).length()).max(1e-30)
}

/// Every reference shape (quads, n-gons, triangles, creases and holes, which the bilinear
/// scheme ignores but for holes) at the corners of its level-2 faces.
#[test]
fn bilinear_lattice_points_are_the_refined_vertices() {
    let (depth, mut checked) = (2, 0);
    for path in fixture_files("reference/shapes", "obj") {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let mesh = read_obj(&path).unwrap();
        let eval = Evaluator::new(&mesh, Scheme::Bilinear).unwrap();
        let (refined, pos) = refine_uniform_levels_f64(&mesh, Scheme::Bilinear, depth).unwrap();
        let faces = refined_faces(&mesh, Scheme::Bilinear, depth);
        assert_eq!(faces.len(), refined.num_faces(), "{name}");
        let diag = diagonal(&mesh);
        for (f, (face, params)) in faces.iter().enumerate() {
            if mesh.is_hole(FaceId(*face)) {
                continue;
            }
            let verts = refined.face_vertices(FaceId(f as u32));
            for (k, p) in params.iter().enumerate() {
                let s = eval
                    .evaluate(Query::new(*face, p[0], p[1]), Derivatives::First)
                    .unwrap();
                let want = pos[verts[k].idx()];
                let d = (s.position - want).length();
                assert!(
                    d <= 1e-12 * diag,
                    "{name}: face {face} at {p:?}: {} vs {want}",
                    s.position
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 10_000, "{checked}");
}

/// UVs of every face-varying option are linear under the bilinear scheme: at the lattice they
/// are the refined face-varying values.
#[test]
fn bilinear_uvs_are_the_refined_values() {
    let mut checked = 0;
    for path in fixture_files("meshes/fvar", "obj") {
        let text = std::fs::read_to_string(&path).unwrap();
        for option in 0..6 {
            let text = format!("{text}\nt facevaryinginterpolateboundary 1/0/0 {option}\n");
            let mut soup = parse_obj(&text).unwrap();
            soup.split_nonmanifold().unwrap();
            let mesh = Mesh::from_soup(&soup).unwrap();
            let eval = Evaluator::new(&mesh, Scheme::Bilinear).unwrap();
            let refined = refine_uniform_levels(&mesh, Scheme::Bilinear, 2).unwrap();
            let fv = refined.uv().unwrap();
            let (offsets, _) = refined.face_lists();
            for (f, (face, params)) in refined_faces(&mesh, Scheme::Bilinear, 2).iter().enumerate()
            {
                for (k, p) in params.iter().enumerate() {
                    let uv = eval
                        .evaluate_uv(Query::new(*face, p[0], p[1]))
                        .unwrap()
                        .unwrap();
                    let want = fv.corner(offsets[f] as usize + k).as_dvec2();
                    assert!(
                        (uv.uv - want).length() < 1e-6,
                        "{path:?} option {option}: {uv:?}"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}

/// Random points: first and second derivatives are those of the positions (central
/// differences; `d2/du2` and `d2/dv2` vanish on bilinear patches), on quads, n-gons and
/// triangles.
#[test]
fn bilinear_derivatives_are_the_differences_of_positions() {
    let mut rng = Rng::splitmix(11);
    for name in [
        "catmark_nonquads",
        "catmark_cube_creases1",
        "loop_icosahedron",
    ] {
        let mesh = read_obj(shape(&format!("{name}.obj"))).unwrap();
        let eval = Evaluator::new(&mesh, Scheme::Bilinear).unwrap();
        let scale = 4.0 * diagonal(&mesh);
        for _ in 0..60 {
            let face = rng.below(mesh.num_faces()) as u32;
            let domain = eval.domain(face).unwrap();
            let margin = 0.02;
            let [u, v] = domain.sample([rng.next_f64(), rng.next_f64(), rng.next_f64()]);
            // Keep the differences inside one tile: pull the point towards its tile's centre.
            let (sub, s, t) = domain.locate(u, v).unwrap();
            let (s, t) = (s.clamp(margin, 1.0 - margin), t.clamp(margin, 1.0 - margin));
            let [u, v] = match domain {
                Domain::SubFaces { .. } => {
                    let [x, y] = domain.corner(sub);
                    [x + s / 2.0, y + t / 2.0]
                }
                _ => [s, t],
            };
            let at = |u: f64, v: f64| {
                eval.evaluate(Query::new(face, u, v), Derivatives::Second)
                    .unwrap()
            };
            let x = at(u, v);
            let h = 1e-5;
            let (pu, mu, pv, mv) = (at(u + h, v), at(u - h, v), at(u, v + h), at(u, v - h));
            let fd = |a: DVec3, b: DVec3| (a - b) / (2.0 * h);
            let close = |a: DVec3, b: DVec3, tol: f64| (a - b).length() <= tol * scale;
            assert!(
                close(fd(pu.position, mu.position), x.du, 1e-6),
                "{name} {face} du"
            );
            assert!(
                close(fd(pv.position, mv.position), x.dv, 1e-6),
                "{name} {face} dv"
            );
            assert!(close(fd(pv.du, mv.du), x.duv, 1e-4), "{name} {face} duv");
            assert_eq!((x.duu, x.dvv), (DVec3::ZERO, DVec3::ZERO));
        }
    }
}
