//! Resource limits: the output-size estimate of `subdiv_rules::budget` against the real output
//! of every path (exact for uniform depth, a bound for adaptive frames and DoI-driven
//! refinement), and the library entry points refusing a deep request on a large cage with the
//! typed error before allocating anything.

use glam::Vec3;
use subdiv::depth::DepthParams;
use subdiv::{DynamicSubdivision, RefineError, SceneError, uniform_limit};
use subdiv_doi::{Aggregate, Dihedral, DoiContext};
use subdiv_mesh::{Camera, Mesh};
use subdiv_redgreen::Balance;
use subdiv_rules::budget::{Limit, estimate, machine_memory};
use subdiv_rules::{Depth, OutputTooLarge, Request, RulesError, Scheme};
use subdiv_slate::SlateError;
use subdiv_stitch::AssemblyError;
use subdiv_tests::{catmull_clark_cages, fixtures, loop_cages};

fn read(rel: &str) -> Mesh {
    subdiv_mesh::read_obj(fixtures().join(rel)).unwrap()
}

/// The pawn: 588 faces with n-gons; depth 12 asks for about 413 GiB.
fn pawn() -> Mesh {
    read("reference/shapes/catmark_pawn.obj")
}

/// The bunny: 3,674 triangles; depth 12 asks for about 1.7 TiB.
fn bunny() -> Mesh {
    read("meshes/tri_bunny_3k.obj")
}

/// The slate tessellations' vertex, face and triangle counts are the estimate's, on every
/// fixture cage of each scheme (n-gons, boundaries, creases) and a cage with holes at depths
/// 0-3.
#[test]
fn uniform_estimate_equals_the_output() {
    let cages = catmull_clark_cages()
        .into_iter()
        .map(|c| (c, Scheme::CatmullClark))
        .chain(loop_cages().into_iter().map(|c| (c, Scheme::Loop)))
        .chain([(
            (
                String::from("open_lefthanded (holes)"),
                read("usd/open_lefthanded.obj"),
            ),
            Scheme::CatmullClark,
        )]);
    let mut checked = 0;
    for ((name, mesh), scheme) in cages {
        for depth in 0..=3 {
            let Ok(t) = uniform_limit(&mesh, scheme, depth) else {
                // Cages a scheme refuses (a doubled triangle) have no output to measure.
                continue;
            };
            let s = estimate(&mesh, Request::Uniform { scheme, depth });
            let what = format!("{name} {scheme:?} depth {depth}");
            assert_eq!(s.vertices, t.positions().len() as u64, "{what}: vertices");
            assert_eq!(s.faces, t.num_faces() as u64, "{what}: faces");
            assert_eq!(s.triangles, t.triangles().len() as u64 / 3, "{what}");
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked}");
}

/// A small deterministic generator (no dependency for a few random depths).
fn lcg(seed: &mut u64) -> u64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    *seed >> 33
}

/// Adaptive frames stay within the bound at their maximum depth: every face at the maximum
/// depth, every face at 0 but one, alternating extremes and random depths, and view-dependent
/// depths; Catmull-Clark (n-gons, UVs, holes) and Loop.
#[test]
fn adaptive_frames_stay_within_the_bound() {
    let cages = [
        (
            read("reference/shapes/catmark_pawn.obj"),
            Scheme::CatmullClark,
        ),
        (
            read("reference/shapes/catmark_cube.obj"),
            Scheme::CatmullClark,
        ),
        (
            read("reference/shapes/catmark_nonquads.obj"),
            Scheme::CatmullClark,
        ),
        (read("meshes/fvar/cube_uv.obj"), Scheme::CatmullClark),
        (read("usd/open_lefthanded.obj"), Scheme::CatmullClark),
        (read("meshes/tri_teapot.obj"), Scheme::Loop),
        (read("reference/shapes/loop_cube.obj"), Scheme::Loop),
    ];
    let mut seed = 7u64;
    for (mesh, scheme) in cages {
        let n = mesh.num_faces();
        for max_depth in [1, 2, 3, 4] {
            let params = DepthParams {
                max_depth,
                ..Default::default()
            };
            let bound = estimate(&mesh, Request::Adaptive { scheme, max_depth });
            let mut node = DynamicSubdivision::with_scheme(mesh.clone(), scheme, params).unwrap();
            let (lo, hi) = mesh.bounds();
            let camera = Camera::eye_relative(lo, hi, Vec3::new(0.3, 0.4, 2.0), 45.0, 320, 240);
            let one_deep = |k: usize| -> Vec<Depth> {
                (0..n).map(|f| if f == k { max_depth } else { 0 }).collect()
            };
            let mut cases: Vec<Vec<Depth>> = vec![
                vec![max_depth; n],
                one_deep(0),
                one_deep(n / 2),
                (0..n)
                    .map(|f| if f % 2 == 0 { max_depth } else { 0 })
                    .collect(),
            ];
            for _ in 0..4 {
                cases.push(
                    (0..n)
                        .map(|_| (lcg(&mut seed) % (u64::from(max_depth) + 1)) as Depth)
                        .collect(),
                );
            }
            for depths in cases {
                node.set_face_depths(Some(depths)).unwrap();
                let g = node.update(&camera, None).unwrap();
                let what = format!("{scheme:?} {n} faces max depth {max_depth}");
                assert!(
                    g.num_triangles() as u64 <= bound.triangles,
                    "{what}: {} triangles, bound {}",
                    g.num_triangles(),
                    bound.triangles
                );
                assert!(
                    g.surface().positions().len() as u64 <= bound.vertices,
                    "{what}: {} vertices, bound {}",
                    g.surface().positions().len(),
                    bound.vertices
                );
            }
            // View-dependent depths too.
            node.set_face_depths(None).unwrap();
            let g = node.update(&camera, None).unwrap();
            assert!(g.num_triangles() as u64 <= bound.triangles);
        }
    }
}

/// DoI-driven refinement: every face selected at every step is the bound exactly (uniform
/// Loop); a partial selection stays within it.
#[test]
fn refine_estimate_bounds_the_refined_mesh() {
    let mesh = read("meshes/tri_teapot.obj");
    for steps in 1..=3 {
        let bound = estimate(&mesh, Request::Refine { steps });
        for (threshold, exact) in [(-1.0, true), (20.0, false)] {
            let opts = subdiv::RefineOptions {
                threshold,
                steps,
                aggregate: Aggregate::Max,
                balance: Balance::Vertex,
            };
            let r =
                subdiv::refine_adaptive(&mesh, &Dihedral, &DoiContext::default(), &opts).unwrap();
            let (v, f) = (
                r.mesh.mesh.num_vertices() as u64,
                r.mesh.mesh.num_faces() as u64,
            );
            if exact {
                assert_eq!((v, f), (bound.vertices, bound.triangles), "{steps} steps");
            } else {
                assert!(v <= bound.vertices && f <= bound.triangles, "{steps} steps");
                assert!(f < bound.triangles, "the threshold selects only some faces");
            }
        }
    }
}

/// The memory error of a refused request: the request, the cage and the machine's memory.
fn assert_memory(e: &OutputTooLarge, request: Request, cage_faces: u64) {
    assert_eq!(e.request, request);
    assert_eq!(e.cage_faces, cage_faces);
    assert!(matches!(e.limit, Limit::Memory { .. }), "{e:?}");
    let text = e.to_string();
    assert!(text.contains("of memory available"), "{text}");
    assert!(
        text.starts_with(&format!(
            "{request} on {} ",
            subdiv_rules::budget::format_count(cage_faces)
        )),
        "{text}"
    );
}

/// Depth 12 on a 588-face or a 3,674-triangle cage is beyond any machine: every uniform entry
/// point refuses it with the typed error (returning at once, nothing allocated).
#[test]
fn uniform_entry_points_refuse_beyond_memory() {
    if machine_memory().is_none() {
        eprintln!("skipping: this platform reports no memory size");
        return;
    }
    let (pawn, bunny) = (pawn(), bunny());
    let cc = Request::Uniform {
        scheme: Scheme::CatmullClark,
        depth: 12,
    };
    let lp = Request::Uniform {
        scheme: Scheme::Loop,
        depth: 12,
    };
    let size = estimate(&pawn, cc);
    assert_eq!(
        size.faces,
        2352 * 4u64.pow(11),
        "the pawn's 2,352 corners as quads"
    );
    match subdiv_rules::tessellate_uniform(&pawn, Scheme::CatmullClark, 12) {
        Err(RulesError::OutputTooLarge(e)) => assert_memory(&e, cc, 588),
        r => panic!("{:?}", r.map(|t| t.num_faces())),
    }
    match subdiv_slate::tessellate(&pawn, 12) {
        Err(SlateError::OutputTooLarge(e)) => {
            assert_memory(&e, cc, 588);
            assert_eq!(e.size, size);
        }
        r => panic!("{:?}", r.map(|t| t.num_faces())),
    }
    match subdiv_slate::tessellate_tri(&bunny, 12) {
        Err(SlateError::OutputTooLarge(e)) => assert_memory(&e, lp, 3674),
        r => panic!("{:?}", r.map(|t| t.num_faces())),
    }
    match uniform_limit(&pawn, Scheme::CatmullClark, 12) {
        Err(SceneError::Slate(SlateError::OutputTooLarge(e))) => assert_memory(&e, cc, 588),
        r => panic!("{:?}", r.map(|t| t.num_faces())),
    }
    match subdiv::Scene::uniform(&bunny, Scheme::Loop, 12) {
        Err(SceneError::Slate(SlateError::OutputTooLarge(e))) => assert_memory(&e, lp, 3674),
        r => panic!("{:?}", r.map(|s| s.faces())),
    }
    match subdiv_rules::refine_uniform_levels(&bunny, Scheme::Loop, 12) {
        Err(RulesError::OutputTooLarge(e)) => assert_memory(&e, lp, 3674),
        r => panic!("{:?}", r.map(|m| m.num_faces())),
    }
}

/// The adaptive path at its deepest maximum depth and DoI-driven refinement by 12 steps are
/// refused by their bounds.
#[test]
fn adaptive_and_refine_entry_points_refuse_beyond_memory() {
    if machine_memory().is_none() {
        eprintln!("skipping: this platform reports no memory size");
        return;
    }
    let (pawn, bunny) = (pawn(), bunny());
    let max_depth = subdiv_stitch::MAX_ADAPTIVE_DEPTH;
    let params = DepthParams {
        max_depth,
        ..Default::default()
    };
    for (mesh, scheme) in [(&pawn, Scheme::CatmullClark), (&bunny, Scheme::Loop)] {
        match DynamicSubdivision::with_scheme(mesh.clone(), scheme, params) {
            Err(AssemblyError::OutputTooLarge(e)) => assert_memory(
                &e,
                Request::Adaptive { scheme, max_depth },
                mesh.num_faces() as u64,
            ),
            r => panic!("{:?}", r.map(|_| ())),
        }
    }
    let opts = subdiv::RefineOptions {
        threshold: 0.0,
        steps: 12,
        aggregate: Aggregate::Max,
        balance: Balance::Vertex,
    };
    match subdiv::refine_adaptive(&bunny, &Dihedral, &DoiContext::default(), &opts) {
        Err(RefineError::OutputTooLarge(e)) => {
            assert_memory(&e, Request::Refine { steps: 12 }, 3674);
            assert!(e.to_string().starts_with(
                "12 refinement steps on 3,674 triangles asks for at most 61,639,491,584 triangles"
            ));
        }
        r => panic!("{:?}", r.map(|r| r.mesh.mesh.num_faces())),
    }
}
