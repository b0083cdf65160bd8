//! Tessellation at any rate: watertight to the bit on every reference shape at random rates,
//! triangles turning with the surface, parameters that evaluate to their points.

use glam::Vec3;
use subdiv_mesh::{EdgeId, Mesh, read_obj};
use subdiv_rules::Scheme;
use subdiv_test_support::{Rng, fixture_files, open_edges};

use super::*;
use crate::{Derivatives, Evaluator, Query};

fn shapes() -> Vec<(String, Mesh, Scheme)> {
    fixture_files("reference/shapes", "obj")
        .into_iter()
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().to_string();
            let scheme = if name.starts_with("loop") {
                Scheme::Loop
            } else {
                Scheme::CatmullClark
            };
            (name, read_obj(&p).unwrap(), scheme)
        })
        .collect()
}

/// Random rates, a few of them large.
fn random_rates(mesh: &Mesh, rng: &mut Rng) -> EdgeRates {
    EdgeRates::from_rates(
        (0..mesh.num_edges())
            .map(|_| {
                if rng.chance(5) {
                    20 + rng.below(60) as u32
                } else {
                    1 + rng.below(7) as u32
                }
            })
            .collect(),
    )
}

/// Every edge of the output has two triangles after welding equal coordinates (every
/// point shared between faces is one point), but those along the cage's boundary and holes:
/// exactly as many as the rates of those cage edges say.
#[test]
fn watertight_to_the_bit_at_random_rates() {
    let mut rng = Rng::splitmix(21);
    for (name, mesh, scheme) in shapes() {
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        for round in 0..3 {
            let rates = if round == 0 {
                EdgeRates::uniform(&mesh, 1)
            } else {
                random_rates(&mesh, &mut rng)
            };
            let t = tessellate_rates(&eval, &rates).unwrap();
            let tris = t.surface.triangles();
            let open = open_edges(&name, t.surface.positions(), &tris);
            let expected: u32 = mesh
                .edges()
                .filter(|&e| {
                    let faces = [e.halfedge(0), e.halfedge(1)]
                        .iter()
                        .filter(|&&h| mesh.face(h).is_some() && !mesh.is_hole(mesh.face(h)))
                        .count();
                    faces == 1
                })
                .map(|e: EdgeId| t.rates[e.idx()])
                .sum();
            assert_eq!(open as u32, expected, "{name} round {round}");
        }
    }
}

/// Each vertex's parameter point evaluates to the vertex (to `f32`), and the triangles turn
/// with the surface: their normals agree with the limit normals at their corners on smooth
/// closed shapes.
#[test]
fn parameters_and_orientation() {
    let mut rng = Rng::splitmix(4);
    for name in [
        "catmark_torus",
        "catmark_pawn",
        "catmark_nonquads",
        "loop_icosahedron",
        "loop_cube",
    ] {
        let scheme = if name.starts_with("loop") {
            Scheme::Loop
        } else {
            Scheme::CatmullClark
        };
        let mesh = read_obj(subdiv_test_support::shape(&format!("{name}.obj"))).unwrap();
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let t = tessellate_rates(&eval, &random_rates(&mesh, &mut rng)).unwrap();
        for (i, &(face, [u, v])) in t.params.iter().enumerate() {
            let s = eval
                .evaluate(Query::new(face, u, v), Derivatives::First)
                .unwrap();
            let p = Vec3::from(t.surface.positions()[i]).as_dvec3();
            assert!((s.position - p).length() < 1e-5, "{name}: vertex {i}");
        }
        let pos = t.surface.positions();
        let nrm = t.surface.normals();
        let mut against = 0;
        let tris = t.surface.triangles();
        for c in tris.chunks(3) {
            let [a, b, d] = [c[0], c[1], c[2]].map(|i| Vec3::from(pos[i as usize]));
            let n = (b - a).cross(d - a);
            let limit: Vec3 = c.iter().map(|&i| Vec3::from(nrm[i as usize])).sum();
            against += usize::from(n.dot(limit) <= 0.0);
        }
        assert!(
            against * 200 <= tris.len() / 3,
            "{name}: {against} of {} triangles turn against the surface",
            tris.len() / 3
        );
    }
}

/// The counts of a lone quad and triangle: rates (2, 3, 4, 5) on a quad give the inner grid
/// of rates 4 x 5 (3 x 4 points) and every side's points once.
#[test]
fn counts_of_a_lone_quad_and_triangle() {
    let quad = Mesh::from_soup(
        &subdiv_mesh::parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap(),
    )
    .unwrap();
    let eval = Evaluator::new(&quad, Scheme::CatmullClark).unwrap();
    let mut rates = vec![0; 4];
    let mut h = quad.face_halfedge(subdiv_mesh::FaceId(0));
    for r in [2, 3, 4, 5] {
        rates[h.edge().idx()] = r;
        h = quad.next(h);
    }
    let t = tessellate_rates(&eval, &EdgeRates::from_rates(rates)).unwrap();
    assert_eq!(t.surface.num_vertices(), 4 + (1 + 2 + 3 + 4) + 3 * 4);
    let tri =
        Mesh::from_soup(&subdiv_mesh::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap())
            .unwrap();
    let eval = Evaluator::new(&tri, Scheme::Loop).unwrap();
    let t = tessellate_rates(&eval, &EdgeRates::uniform(&tri, 6)).unwrap();
    // 28 lattice points, 36 triangles: the uniform rate-6 triangle lattice.
    assert_eq!(
        (t.surface.num_vertices(), t.surface.triangles().len() / 3),
        (28, 36)
    );
}

/// A cube with every edge semi-sharp (sharpness 5: a band of `2 · 2^-5` of a face): coarse
/// rates draw each crease with one-sided normals taken just beyond the band, so the faces at an
/// edge point or a cage vertex carry normals far apart; rates that resolve the band (two steps
/// across it) keep the exact (smooth) normal there, one per point.
#[test]
fn semi_sharp_creases_are_one_sided_below_the_tessellation() {
    let mut obj = String::from(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
         f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
    );
    for (a, b) in [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ] {
        obj.push_str(&format!("t crease 2/1/0 {a} {b} 5\n"));
    }
    let cube = Mesh::from_soup(&subdiv_mesh::parse_obj(&obj).unwrap()).unwrap();
    let eval = Evaluator::new(&cube, Scheme::CatmullClark).unwrap();
    // The turned corners: (at the cube's corners, at points along its edges).
    let turned = |rate: u32| {
        let t = tessellate_rates(&eval, &EdgeRates::uniform(&cube, rate)).unwrap();
        let (normals, tris) = (t.surface.normals(), t.surface.triangles());
        let (mut at_vertices, mut on_edges) = (0, 0);
        for (corner, n) in t.surface.corner_normals() {
            let v = tris[*corner as usize] as usize;
            if Vec3::from(*n)
                .angle_between(Vec3::from(normals[v]))
                .to_degrees()
                > 20.0
            {
                let [u, w] = t.params[v].1;
                let at_vertex = [u, w].iter().all(|&x| x == 0.0 || x == 1.0);
                *(if at_vertex {
                    &mut at_vertices
                } else {
                    &mut on_edges
                }) += 1;
            }
        }
        (at_vertices, on_edges)
    };
    // Rate 4: 3 inner points on each of 12 edges, both faces turned away from the blend; at
    // each of the 8 corners (whose exact normal is the smooth diagonal), its 3 faces.
    let (at_vertices, on_edges) = turned(4);
    assert!(on_edges >= 2 * 12 * 3, "{on_edges}");
    assert!(at_vertices >= 8 * 3, "{at_vertices}");
    // Rate 16 has one step across the band (1/16): still one-sided, taken half a step in.
    let (at_vertices, on_edges) = turned(16);
    assert!(
        on_edges >= 2 * 12 * 15 && at_vertices >= 8 * 3,
        "{on_edges} {at_vertices}"
    );
    // Rate 32 resolves the band (two steps of 1/32 across it): the exact normals everywhere.
    assert_eq!(turned(32), (0, 0));
}

/// The bilinear scheme at random rates: watertight to the bit like the others, and its patches
/// meet with a crease at every cage edge, so every corner (on an edge or not) carries its own
/// face's normal: on the planar faces of the cube, the normal of its triangle.
#[test]
fn bilinear_dicing_is_watertight_with_each_face_its_own_normal() {
    let mut rng = Rng::splitmix(5);
    for name in ["catmark_cube", "catmark_nonquads"] {
        let mesh = read_obj(subdiv_test_support::shape(&format!("{name}.obj"))).unwrap();
        let eval = Evaluator::new(&mesh, Scheme::Bilinear).unwrap();
        for _ in 0..3 {
            let t = tessellate_rates(&eval, &random_rates(&mesh, &mut rng)).unwrap();
            let (s, tris) = (&t.surface, t.surface.triangles());
            // Open only along the cage's boundary, one edge per step of its rate.
            let boundary: u32 = mesh
                .edges()
                .filter(|&e| mesh.is_boundary_edge(e))
                .map(|e| t.rates[e.idx()])
                .sum();
            assert_eq!(
                open_edges(name, s.positions(), &tris) as u32,
                boundary,
                "{name}"
            );
            if name != "catmark_cube" {
                continue;
            }
            for (k, tri) in tris.chunks(3).enumerate() {
                let p = [0, 1, 2].map(|c| Vec3::from(s.positions()[tri[c] as usize]));
                let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                for c in 0..3 {
                    let drawn = Vec3::from(s.corner_normal(3 * k + c)).normalize();
                    assert!(
                        drawn.dot(n) > 0.9999,
                        "{name} triangle {k} corner {c}: {drawn} vs {n}"
                    );
                }
            }
        }
    }
}
