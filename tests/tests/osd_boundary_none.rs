//! `interpolateboundary none` as OpenSubdiv 3.5 applies it: every face at a vertex
//! with a boundary edge not tagged infinitely sharp is hidden, the faces at a vertex whose
//! boundary edges are all tagged infinitely sharp are drawn (`BoundaryNoneRule` in
//! `subdiv-mesh`, applied by `Mesh::from_soup` as holes).
//!
//! - The manifold cages of `fixtures/boundary_none/` (both schemes; fully sharp rings, mixed
//!   sides, a semi-sharp boundary edge, an n-gon, a corner tag) against `ref_osd ... local` at
//!   levels 1-3: counts, faces, positions within 1e-5 x diagonal, normals within 0.05 degrees;
//!   whole-mesh path and slates.
//! - Every path hides the same faces: the adaptive frames (`DynamicSubdivision`, both schemes)
//!   at one depth cover exactly the points the uniform tessellation's drawn faces use, with
//!   as many triangles, on those cages and on fuzz-osd's random `none` cages.

use glam::{DVec3, Vec3};
use subdiv::DynamicSubdivision;
use subdiv_depth::DepthParams;
use subdiv_mesh::{Camera, Mesh, read_obj};
use subdiv_rules::{Depth, Scheme, tessellate_uniform};
use subdiv_tests::osd_compare::{Tessellator, assert_fixture_dir_agrees};
use subdiv_tests::osd_gen::random_cage;
use subdiv_tests::{PointGrid, fixture_files};

/// fuzz-osd's normal tolerance (degrees).
const NORMAL_DEG: f64 = 0.05;

fn scheme_of(name: &str) -> Scheme {
    if name.ends_with("_loop") {
        Scheme::Loop
    } else {
        Scheme::CatmullClark
    }
}

#[test]
fn boundary_none_cages_agree_with_opensubdiv() {
    assert_fixture_dir_agrees("boundary_none", NORMAL_DEG, 24, |_| {
        vec![Tessellator::Uniform, Tessellator::Slate]
    });
}

/// The points the drawn faces of the uniform tessellation use, and its triangle count.
fn uniform_cover(mesh: &Mesh, scheme: Scheme, depth: Depth) -> (Vec<DVec3>, usize) {
    let t = tessellate_uniform(mesh, scheme, depth).unwrap();
    let mut used = vec![false; t.positions().len()];
    let mut triangles = 0;
    for w in t.face_offsets().windows(2) {
        let f = &t.face_indices()[w[0] as usize..w[1] as usize];
        triangles += f.len() - 2;
        for &i in f {
            used[i as usize] = true;
        }
    }
    let points = (0..used.len())
        .filter(|&i| used[i])
        .map(|i| Vec3::from(t.positions()[i]).as_dvec3())
        .collect();
    (points, triangles)
}

/// The points the triangles of an adaptive frame with every face at `depth` use, and its
/// triangle count.
fn adaptive_cover(mesh: &Mesh, scheme: Scheme, depth: Depth) -> (Vec<DVec3>, usize) {
    let params = DepthParams {
        max_depth: 3,
        ..DepthParams::default()
    };
    let mut node = DynamicSubdivision::with_scheme(mesh.clone(), scheme, params).unwrap();
    node.set_face_depths(Some(vec![depth; mesh.num_faces()]))
        .unwrap();
    let (lo, hi) = mesh.bounds();
    let camera = Camera::eye_relative(lo, hi, Vec3::new(0.2, 0.3, 3.0), 45.0, 640, 480);
    let g = node.update(&camera, None).unwrap();
    let mut used = vec![false; g.surface().positions().len()];
    for &i in g.surface().face_indices() {
        used[i as usize] = true;
    }
    let points = (0..used.len())
        .filter(|&i| used[i])
        .map(|i| Vec3::from(g.surface().positions()[i]).as_dvec3())
        .collect();
    (points, g.surface().face_indices().len() / 3)
}

/// Every point of `a` has one of `b` within `tol`; the first that has not, if any.
fn uncovered(a: &[DVec3], b: &[DVec3], tol: f64) -> Option<DVec3> {
    let grid = PointGrid::new(b, tol.max(1e-12) * 4.0);
    a.iter().copied().find(|&p| grid.nearest(p).1 > tol)
}

/// Uniform and adaptive at depths 1-3 cover the same points with as many triangles.
fn same_cover(name: &str, mesh: &Mesh, scheme: Scheme, failures: &mut Vec<String>) {
    let (lo, hi) = mesh.bounds();
    let tol = 1e-5 * (hi - lo).length() as f64;
    for depth in 1..=3 {
        let (u, ut) = uniform_cover(mesh, scheme, depth);
        let (a, at) = adaptive_cover(mesh, scheme, depth);
        if ut != at {
            failures.push(format!(
                "{name} depth {depth}: {at} adaptive triangles, {ut} uniform"
            ));
        }
        if let Some(p) = uncovered(&a, &u, tol) {
            failures.push(format!(
                "{name} depth {depth}: adaptive draws {p}, uniform does not"
            ));
        }
        if let Some(p) = uncovered(&u, &a, tol) {
            failures.push(format!(
                "{name} depth {depth}: uniform draws {p}, adaptive does not"
            ));
        }
    }
}

#[test]
fn adaptive_frames_hide_the_faces_the_uniform_path_hides() {
    let mut failures = Vec::new();
    let mut cages = 0;
    for file in fixture_files("boundary_none", "obj") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        let mesh = read_obj(&file).unwrap();
        same_cover(&name, &mesh, scheme_of(&name), &mut failures);
        cages += 1;
    }
    // fuzz-osd's random cages with `interpolateboundary none` and a boundary (seed 5).
    let (mut random, mut hiding) = (0, 0);
    for i in 0..400 {
        let c = random_cage(5, i);
        if c.boundary != Some(0) {
            continue;
        }
        let mesh = c.mesh().unwrap();
        if mesh.is_closed() || mesh.num_faces() > 60 {
            continue;
        }
        let scheme = if c.loop_scheme {
            Scheme::Loop
        } else {
            Scheme::CatmullClark
        };
        hiding += usize::from(mesh.holes().iter().filter(|&&h| h).count() > c.holes.len());
        same_cover(&format!("seed 5 cage {i}"), &mesh, scheme, &mut failures);
        random += 1;
        if random == 24 {
            break;
        }
    }
    eprintln!("{cages} fixture cages, {random} random none cages ({hiding} hiding faces)");
    assert!(
        failures.is_empty(),
        "{} disagreements:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        cages >= 4 && random >= 12 && hiding >= 6,
        "{cages} {random} {hiding}"
    );
}
