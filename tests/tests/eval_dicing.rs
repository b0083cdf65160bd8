//! Dicing by pixels is watertight to the bit on every fixture cage from five cameras: after
//! welding identical coordinates every edge of the output has two triangles but those along
//! the cage's boundary and holes, exactly as many as those cage edges' rates. (A non-manifold
//! cage is refined as manifold pieces, each with its own copy of a non-manifold edge: each
//! piece is checked by index, its copies of the edge counted as its boundary.)

use subdiv::eval::{Dicing, Evaluator, dice};
use subdiv_mesh::{CageOptions, Camera, glam::Vec3, read_cage};
use subdiv_test_support::{indexed_open_edges, open_edges};
use subdiv_tests::eval_compare::eval_fixtures;
use subdiv_tests::fixtures;

/// Five views: four around and above or below the cage, one close up (much of it off screen).
const VIEWS: [[f32; 3]; 5] = [
    [0.8, 0.5, 2.2],
    [-2.0, 0.3, 0.5],
    [0.2, -2.5, 0.4],
    [1.5, 1.5, -1.5],
    [0.3, 0.2, 0.7],
];

#[test]
fn dicing_is_watertight_on_every_fixture_from_five_cameras() {
    let (mut runs, mut triangles) = (0, 0usize);
    for (rel, scheme) in eval_fixtures(&fixtures()) {
        let cage = read_cage(fixtures().join(&rel), &CageOptions::default()).unwrap();
        let mesh = &cage.mesh;
        let eval = Evaluator::new(mesh, scheme).unwrap();
        let (lo, hi) = mesh.bounds();
        for (k, view) in VIEWS.iter().enumerate() {
            let camera = Camera::eye_relative(lo, hi, Vec3::from(*view), 45.0, 200, 150);
            let t = dice(&eval, &camera, &Dicing::new(3.0)).unwrap();
            let tris = t.surface.triangles();
            let name = format!("{rel} view {k}");
            let open = if cage.nonmanifold.is_empty() {
                open_edges(&name, t.surface.positions(), &tris)
            } else {
                indexed_open_edges(&name, &tris)
            };
            let expected: u32 = mesh
                .edges()
                .filter(|&e| {
                    let sides = [e.halfedge(0), e.halfedge(1)];
                    sides
                        .iter()
                        .filter(|&&h| mesh.face(h).is_some() && !mesh.is_hole(mesh.face(h)))
                        .count()
                        == 1
                })
                .map(|e| t.rates[e.idx()])
                .sum();
            assert_eq!(open as u32, expected, "{name}: open edges");
            runs += 1;
            triangles += tris.len() / 3;
        }
    }
    println!("eval-dicing: {runs} tessellations, {triangles} triangles, all watertight");
    assert!(runs >= 5 * 90, "{runs}");
}
