use glam::Vec3;
use subdiv_mesh::{Mesh, read_obj, sway};
use subdiv_rules::{LimitMesh, Scheme};
use subdiv_slate::{UniformTessellator, tessellate, tessellate_tri};
use subdiv_test_support::{fixture, max_deviation, shape};

use crate::{MAX_STENCIL_DEPTH, StencilTable, StencilTessellator};

fn load(path: std::path::PathBuf) -> Mesh {
    read_obj(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn fresh(mesh: &Mesh, scheme: Scheme, depth: subdiv_rules::Depth) -> LimitMesh {
    match scheme {
        Scheme::Loop => tessellate_tri(mesh, depth).unwrap(),
        _ => tessellate(mesh, depth).unwrap(),
    }
}

/// [`max_deviation`] of two surfaces with the same faces.
fn compare(a: &LimitMesh, b: &LimitMesh, size: f32) -> (f32, f32) {
    assert_eq!(a.face_indices(), b.face_indices());
    max_deviation(
        (a.positions(), a.normals()),
        (b.positions(), b.normals()),
        size,
    )
}

fn size(mesh: &Mesh) -> f32 {
    let (lo, hi) = mesh.bounds();
    (hi - lo).length()
}

/// The cages the tables are checked on: regular quads, extraordinary vertices, n-gons,
/// boundaries, semi-sharp and sharp creases, Loop.
fn cages() -> Vec<(Mesh, Scheme, &'static str)> {
    let cc = |f: &str| (load(shape(f)), Scheme::CatmullClark, "");
    let lp = |f: &str| (load(shape(f)), Scheme::Loop, "");
    let mut v: Vec<(Mesh, Scheme, &'static str)> = vec![
        cc("catmark_pawn.obj"),
        cc("catmark_helmet.obj"),
        cc("catmark_nonquads.obj"),
        cc("catmark_pole8.obj"),
        cc("catmark_torus_creases0.obj"),
        cc("catmark_tent_creases0.obj"),
        lp("loop_cubes_semisharp.obj"),
        lp("loop_pole8.obj"),
        lp("loop_cube_creases0.obj"),
    ];
    v.push((
        load(fixture("meshes/cc_3torus.obj")),
        Scheme::CatmullClark,
        "",
    ));
    v
}

/// Every frame of a swaying cage through the table is the fresh slate tessellation of that
/// frame's cage, to rounding, with the same faces; the faces are written on the first frame
/// only.
#[test]
fn every_frame_through_the_table_is_the_fresh_tessellation_to_rounding() {
    let mut ring_stencils = 0;
    for (mesh, scheme, _) in cages() {
        for depth in 1..=MAX_STENCIL_DEPTH {
            let mut t = StencilTessellator::new(&mesh, scheme, depth).unwrap();
            let name = format!("{scheme:?} depth {depth}, {} faces", mesh.num_faces());
            let table = t.stencils().expect("a table");
            ring_stencils += table.ring_stencils();
            assert!(t.surface().topology_written());
            let s = size(&mesh);
            // The layout's own frame is the slates'.
            assert_eq!(*t.surface(), fresh(&mesh, scheme, depth), "{name}");
            let mut frame = mesh.clone();
            let mut moved = Vec::new();
            for i in 0..4 {
                sway(mesh.positions(), i, 8, &mut moved);
                frame.positions_mut().copy_from_slice(&moved);
                let got = t.update(&frame).unwrap();
                assert!(!got.topology_written(), "{name}");
                let (d, a) = compare(got, &fresh(&frame, scheme, depth), s);
                assert!(d < 1e-6 && a < 1e-4, "{name} frame {i}: {d} {a}");
            }
            assert_eq!(t.layouts_built(), 1);
        }
    }
    // Cage vertices take their rings' masks.
    assert!(ring_stencils > 0);
}

/// The table's output does not depend on the number of threads.
#[test]
fn the_frames_do_not_depend_on_the_thread_count() {
    let mesh = load(shape("catmark_pawn.obj"));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut t = StencilTessellator::new(&mesh, Scheme::CatmullClark, 3).unwrap();
            let mut moved = mesh.clone();
            moved.positions_mut()[9] += Vec3::splat(0.05);
            t.update(&moved).unwrap().clone()
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(5));
}

/// A change of topology lays the cage out again, with its own table; a frame with a bad
/// point is an error and keeps the last surface.
#[test]
fn a_new_topology_gets_a_new_table_and_a_bad_frame_keeps_the_last_surface() {
    let mesh = load(shape("catmark_pawn.obj"));
    let mut t = StencilTessellator::new(&mesh, Scheme::CatmullClark, 2).unwrap();
    let mut sharp = mesh.clone();
    sharp.set_edge_sharpness(subdiv_mesh::EdgeId(3), 2.5);
    let got = t.update(&sharp).unwrap().clone();
    assert!(got.topology_written());
    assert_eq!(t.layouts_built(), 2);
    assert!(t.stencils().is_some());
    let (d, a) = compare(&got, &fresh(&sharp, Scheme::CatmullClark, 2), size(&mesh));
    assert!(d < 1e-6 && a < 1e-4, "{d} {a}");
    for x in [f32::INFINITY, f32::NAN] {
        let mut bad = sharp.clone();
        bad.positions_mut()[7].y = x;
        let e = t.update(&bad).unwrap_err();
        assert!(e.to_string().contains("vertex 7"), "{e}");
        assert_eq!(*t.surface(), got);
    }
}

/// Where no table is made (deeper than the tables go, or one-sided normals at an infinitely
/// sharp crease) the slates run every frame, bit for bit the slate tessellator.
#[test]
fn without_a_table_the_frames_are_the_slates() {
    let mesh = load(shape("catmark_pawn.obj"));
    let mut sharp = mesh.clone();
    sharp.set_edge_sharpness(subdiv_mesh::EdgeId(3), 10.0);
    for (cage, depth) in [(&mesh, MAX_STENCIL_DEPTH + 1), (&sharp, 2)] {
        let mut t = StencilTessellator::new(cage, Scheme::CatmullClark, depth).unwrap();
        assert!(t.stencils().is_none());
        let mut u = UniformTessellator::new(cage, Scheme::CatmullClark, depth).unwrap();
        let mut frame = cage.clone();
        frame.positions_mut()[5] += Vec3::splat(0.1);
        assert_eq!(t.update(&frame).unwrap(), u.update(&frame).unwrap());
    }
}

/// A table built for a cage applies to any other positions: the stencils are the limit's
/// linear maps, checked against the evaluator at random points of a randomly moved cage.
#[test]
fn a_table_is_the_evaluators_limit_at_its_points() {
    use subdiv_eval::{Derivatives, Evaluator, Query, random_queries};
    use subdiv_rules::VertexParams;
    for (mesh, scheme, _) in cages() {
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let queries: Vec<Query> = random_queries(&eval, 300, 7);
        let params = VertexParams {
            face: queries.iter().map(|q| q.face).collect(),
            uv: queries.iter().map(|q| [q.u as f32, q.v as f32]).collect(),
        };
        let table = StencilTable::new(&mesh, scheme, &params, 0).unwrap();
        let mut moved = mesh.clone();
        for (i, p) in moved.positions_mut().iter_mut().enumerate() {
            let a = i as f32 * 0.7;
            *p += Vec3::new(a.sin(), (1.3 * a).cos(), (0.4 * a).sin()) * 0.05 * size(&mesh);
        }
        let n = queries.len();
        let (mut pos, mut nrm) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        table.apply(&moved, &mut pos, &mut nrm).unwrap();
        let eval = Evaluator::new(&moved, scheme).unwrap();
        for (i, (&p, &q)) in params.face.iter().zip(&params.uv).enumerate() {
            let s = eval
                .evaluate(
                    Query::new(p, f64::from(q[0]), f64::from(q[1])),
                    Derivatives::First,
                )
                .unwrap();
            let d = s.position.as_vec3().distance(Vec3::from(pos[i])) / size(&mesh);
            assert!(d < 2e-6, "{scheme:?} point {i}: {d}");
            let want = s.normal().as_vec3();
            if want != Vec3::ZERO {
                let a = want.dot(Vec3::from(nrm[i])).clamp(-1.0, 1.0).acos();
                assert!(a < 1e-3, "{scheme:?} point {i}: normal {a}");
            }
        }
    }
}
/// A frame reads little: faces alike keep one copy of their weights (the pawn is mostly
/// regular quads), and points shared by faces go where they fill the faces' blocks of eight
/// (the bunny's triangles hold eight points each at depth 2, but not as the slates own them).
#[test]
fn faces_alike_share_weights_and_shared_points_fill_blocks() {
    let pawn = load(shape("catmark_pawn.obj"));
    let t = StencilTessellator::new(&pawn, Scheme::CatmullClark, 3).unwrap();
    let table = t.stencils().unwrap();
    // Unshared: 16 support vertices, 12 bytes each, per point.
    let unshared = table.num_points() * 16 * 12;
    assert!(
        table.bytes() * 8 < unshared,
        "{} of {unshared}",
        table.bytes()
    );
    let bunny = load(fixture("meshes/tri_bunny_3k.obj"));
    let t = StencilTessellator::new(&bunny, Scheme::Loop, 2).unwrap();
    let table = t.stencils().unwrap();
    let lanes: u32 = table.groups.iter().map(|g| g.blocks).sum::<u32>() * 8;
    assert!(
        f64::from(lanes) < 1.15 * table.num_points() as f64,
        "{lanes} lanes for {} points",
        table.num_points()
    );
}

/// The portable kernel (CPUs without AVX2 and FMA) gives the fused one's frame to rounding.
#[test]
fn the_portable_kernel_is_the_fused_one_to_rounding() {
    for (mesh, scheme) in [
        (load(shape("catmark_helmet.obj")), Scheme::CatmullClark),
        (load(shape("loop_pole8.obj")), Scheme::Loop),
    ] {
        let t = StencilTessellator::new(&mesh, scheme, 2).unwrap();
        let table = t.stencils().unwrap();
        let mut moved = Vec::new();
        sway(mesh.positions(), 2, 8, &mut moved);
        let mut frame = mesh.clone();
        frame.positions_mut().copy_from_slice(&moved);
        let run = |portable: bool| {
            crate::apply::PORTABLE.with(|p| p.set(portable));
            let mut s = t.surface().clone();
            let (p, n) = s.points_and_normals_mut();
            table.apply(&frame, p, n).unwrap();
            crate::apply::PORTABLE.with(|p| p.set(false));
            s
        };
        let (d, a) = compare(&run(true), &run(false), size(&mesh));
        assert!(d < 1e-6 && a < 1e-4, "{d} {a}");
        assert_eq!(run(true), run(true));
    }
}
/// A table is made from any frame of a cage, not only a rest pose (a swayed pawn at depth 4:
/// its checks sum each stencil about the face, as a frame does, where sums about the origin
/// lose the small derivatives near its pole), and its frames are the fresh tessellations.
#[test]
fn a_table_is_made_from_any_frame() {
    let mesh = load(shape("catmark_pawn.obj"));
    let mut moved = Vec::new();
    sway(mesh.positions(), 0, 48, &mut moved);
    let mut frame = mesh.clone();
    frame.positions_mut().copy_from_slice(&moved);
    let mut t = StencilTessellator::new(&frame, Scheme::CatmullClark, 4).unwrap();
    assert!(t.stencils().is_some());
    sway(mesh.positions(), 5, 48, &mut moved);
    frame.positions_mut().copy_from_slice(&moved);
    let got = t.update(&frame).unwrap();
    let (d, a) = compare(got, &fresh(&frame, Scheme::CatmullClark, 4), size(&mesh));
    assert!(d < 1e-6 && a < 1e-4, "{d} {a}");
}

/// Every cage of the reference shapes, the watertightness fuzz finds and the non-manifold
/// fixtures, under each scheme that takes it, at depths 2 and 3: the tessellator makes a table
/// or runs the slates, and its frames are the fresh tessellations (to rounding through a table,
/// bit for bit without one).
#[test]
fn every_fixture_cage_moves_as_its_fresh_tessellations() {
    use subdiv_test_support::fixture_files;
    let mut files = fixture_files("reference/shapes", "obj");
    files.extend(fixture_files("osd_watertight", "obj"));
    files.extend(fixture_files("nonmanifold", "obj"));
    let (mut tables, mut slates) = (0, 0);
    for path in files {
        let Ok(mesh) = read_obj(&path) else { continue };
        for scheme in [Scheme::CatmullClark, Scheme::Loop] {
            for depth in [2, 3] {
                let Ok(mut t) = StencilTessellator::new(&mesh, scheme, depth) else {
                    continue;
                };
                let name = format!("{} {scheme:?} depth {depth}", path.display());
                let with_table = t.stencils().is_some();
                let mut moved = Vec::new();
                sway(mesh.positions(), 3, 8, &mut moved);
                let mut frame = mesh.clone();
                frame.positions_mut().copy_from_slice(&moved);
                let got = t.update(&frame).unwrap().clone();
                let want = fresh(&frame, scheme, depth);
                if with_table {
                    tables += 1;
                    let (d, a) = compare(&got, &want, size(&mesh));
                    assert!(d < 1e-6 && a < 1e-4, "{name}: {d} {a}");
                } else {
                    slates += 1;
                    assert_eq!(got, want, "{name}");
                }
            }
        }
    }
    assert!(
        tables > 50 && slates > 0,
        "{tables} tables, {slates} without"
    );
}
