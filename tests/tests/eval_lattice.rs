//! At the lattice points of a uniform tessellation (the vertices of the level-d mesh, `d` = 2,
//! 1 for the large meshes) the evaluation is the slates' limit points and normals, on every
//! fixture cage: positions within 1e-6 x diagonal, normals within 0.01 degrees of the vertex
//! normal or of one of the point's one-sided corner normals. The slates take OpenSubdiv's
//! limit masks at the tessellation's level; where those move with the level (darts, valence 2,
//! crease and corner sectors that are not a regular half-plane) the evaluation is the limit
//! instead, and the test checks exactly that: the slate point is the level-d masks' and the
//! masks a few levels deeper differ.

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use subdiv::eval::{Derivatives, Evaluator, Query, Sample, refined_faces};
use subdiv::uniform_limit;
use subdiv_mesh::{CageOptions, FaceId, Mesh, read_cage};
use subdiv_rules::{Ring, Scheme, refine_uniform_levels_f64};
use subdiv_tests::eval_compare::eval_fixtures;
use subdiv_tests::fixtures;

/// The slate vertices near a point: a grid of cells of `cell`.
struct Near {
    cell: f64,
    grid: HashMap<[i64; 3], Vec<u32>>,
}

impl Near {
    fn new(points: &[[f32; 3]], cell: f64) -> Near {
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (i, p) in points.iter().enumerate() {
            grid.entry(Self::key(Vec3::from(*p).as_dvec3(), cell))
                .or_default()
                .push(i as u32);
        }
        Near { cell, grid }
    }

    fn key(p: DVec3, cell: f64) -> [i64; 3] {
        (p / cell).floor().as_i64vec3().to_array()
    }

    /// The vertices within a cell of `p`.
    fn around(&self, p: DVec3) -> impl Iterator<Item = u32> + '_ {
        let k = Self::key(p, self.cell);
        (-1..=1).flat_map(move |x| {
            (-1..=1).flat_map(move |y| {
                (-1..=1).flat_map(move |z| {
                    self.grid
                        .get(&[k[0] + x, k[1] + y, k[2] + z])
                        .into_iter()
                        .flatten()
                        .copied()
                })
            })
        })
    }
}

/// The level-d masks' limit and the masks' limit `extra` levels deeper at vertex `v`, with the
/// one-sided normal of `face`'s side.
fn masks(
    m: &Mesh,
    pos: &[DVec3],
    v: subdiv_mesh::VertexId,
    face: FaceId,
    scheme: Scheme,
    extra: usize,
) -> [(DVec3, DVec3); 2] {
    let origin = pos[v.idx()];
    let fi = m.outgoing(v).position(|h| m.face(h) == face).unwrap_or(0);
    let mut ring = Ring::new();
    ring.load_at(m, |w| pos[w.idx()] - origin, v, scheme);
    let mut sided = Vec::new();
    let mut at = |r: &mut Ring| {
        let (p, n) = r.limit_sided(&mut sided);
        (p + origin, sided.get(fi).copied().unwrap_or(n))
    };
    let first = at(&mut ring.clone());
    for _ in 0..extra {
        ring.refine();
    }
    [first, at(&mut ring)]
}

#[test]
fn lattice_points_are_the_slates_limit_points_and_normals() {
    let (mut checked, mut moving, mut cages) = (0usize, 0usize, 0usize);
    let mut failures = Vec::new();
    for (rel, scheme) in eval_fixtures(&fixtures()) {
        let mesh = read_cage(fixtures().join(&rel), &CageOptions::default())
            .unwrap()
            .mesh;
        let depth = if mesh.num_faces() > 1000 { 1 } else { 2 };
        let slates = uniform_limit(&mesh, scheme, depth).unwrap();
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let (lo, hi) = mesh.bounds();
        let diag = f64::from((hi - lo).length());
        let (refined, pos) = refine_uniform_levels_f64(&mesh, scheme, depth).unwrap();
        let faces = refined_faces(&mesh, scheme, depth);
        let mut queries = Vec::new();
        let mut corners = Vec::new();
        for (f, (face, params)) in faces.iter().enumerate() {
            if mesh.is_hole(FaceId(*face)) {
                continue;
            }
            for (k, p) in params.iter().enumerate() {
                queries.push(Query::new(*face, p[0], p[1]));
                corners.push((f, refined.face_vertices(FaceId(f as u32))[k]));
            }
        }
        let mut samples = vec![Sample::default(); queries.len()];
        eval.evaluate_many(&queries, Derivatives::First, &mut samples)
            .unwrap();
        let near = Near::new(slates.positions(), 1e-4 * diag);
        // The one-sided normals of each slate vertex.
        let mut sided: HashMap<u32, Vec<DVec3>> = HashMap::new();
        for &(c, n) in slates.corner_normals() {
            let v = slates.face_indices()[c as usize];
            sided.entry(v).or_default().push(Vec3::from(n).as_dvec3());
        }
        cages += 1;
        for ((q, s), &(f, v)) in queries.iter().zip(&samples).zip(&corners) {
            checked += 1;
            let candidates: Vec<u32> = near.around(s.position).collect();
            let dist = |i: u32| {
                (Vec3::from(slates.positions()[i as usize]).as_dvec3() - s.position).length()
            };
            let best = candidates
                .iter()
                .copied()
                .min_by(|&a, &b| dist(a).total_cmp(&dist(b)));
            let normals_of = |i: u32| {
                let mut n = vec![Vec3::from(slates.normals()[i as usize]).as_dvec3()];
                n.extend(sided.get(&i).into_iter().flatten());
                n
            };
            let angle = |i: u32| {
                normals_of(i)
                    .iter()
                    .map(|n| {
                        if *n == DVec3::ZERO || s.normal() == DVec3::ZERO {
                            0.0
                        } else {
                            n.angle_between(s.normal()).to_degrees()
                        }
                    })
                    .fold(f64::INFINITY, f64::min)
            };
            // Coincident copies (the pieces of a non-manifold cage) each have their sheet's normal.
            let here: Vec<u32> = candidates
                .iter()
                .copied()
                .filter(|&i| dist(i) <= 1e-6 * diag)
                .collect();
            if here.iter().any(|&i| angle(i) <= 0.01) {
                continue;
            }
            // The masks move at this vertex: the slates' point is theirs at level d.
            let [(p0, n0), (p1, n1)] = masks(&refined, &pos, v, FaceId(f as u32), scheme, 8);
            let moved =
                (p1 - p0).length() > 1e-9 * diag || n1.angle_between(n0).to_degrees() > 0.01;
            let slate_is_masks = near.around(p0).any(|i| {
                let sp = Vec3::from(slates.positions()[i as usize]).as_dvec3();
                (sp - p0).length() <= 1e-6 * diag
                    && normals_of(i)
                        .iter()
                        .any(|n| *n == DVec3::ZERO || n.angle_between(n0).to_degrees() <= 0.01)
            });
            if moved && slate_is_masks {
                moving += 1;
            } else {
                let d = best.map_or(f64::INFINITY, dist) / diag;
                let a = here.iter().map(|&i| angle(i)).fold(f64::INFINITY, f64::min);
                failures.push(format!(
                    "{rel} face {} ({}, {}): {d:.2e} x diagonal, {a:.4} deg",
                    q.face, q.u, q.v
                ));
            }
        }
    }
    println!(
        "eval-lattice: {cages} cages, {checked} lattice points; {moving} where OpenSubdiv's masks move with the level (the slates take the level's, the evaluation the limit)"
    );
    assert!(
        failures.is_empty(),
        "{} points differ from the slates, first: {:#?}",
        failures.len(),
        &failures[..failures.len().min(12)]
    );
    assert!(checked > 100_000, "{checked}");
}
