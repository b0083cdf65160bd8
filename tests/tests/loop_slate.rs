//! The triangular (Loop) slates against the whole-mesh Loop path at depths 0-5, thread-count
//! independence and watertightness.

use std::collections::{HashMap, HashSet};

use glam::DVec3;
use subdiv_rules::{LimitMesh, Scheme, tessellate_uniform};
use subdiv_test_support::indexed_open_edges;
use subdiv_tests::{PointGrid, canonical_face, loop_cages};

fn dv(p: &[f32; 3]) -> DVec3 {
    glam::Vec3::from(*p).as_dvec3()
}

/// Matches `a`'s points to `b`'s (one to one, within `tol`) and `a`'s faces to `b`'s; returns
/// the largest position error and normal angle (degrees).
fn compare(a: &LimitMesh, b: &LimitMesh, tol: f64) -> Result<(f64, f64), String> {
    if a.positions().len() != b.positions().len() || a.num_faces() != b.num_faces() {
        return Err(format!(
            "counts {} / {} vs {} / {}",
            a.positions().len(),
            a.num_faces(),
            b.positions().len(),
            b.num_faces()
        ));
    }
    let pb: Vec<DVec3> = b.positions().iter().map(dv).collect();
    let grid = PointGrid::new(&pb, (tol * 100.0).max(1e-9));
    let mut map = vec![0usize; a.positions().len()];
    let (mut max_err, mut max_deg) = (0.0f64, 0.0f64);
    for (i, p) in a.positions().iter().enumerate() {
        let (j, d) = grid.nearest(dv(p));
        map[i] = j;
        max_err = max_err.max(d);
        let (na, nb) = (dv(&a.normals()[i]), dv(&b.normals()[j]));
        if na.length() > 0.5 && nb.length() > 0.5 {
            let deg = na.normalize().dot(nb.normalize()).clamp(-1.0, 1.0).acos();
            max_deg = max_deg.max(deg.to_degrees());
        }
    }
    if max_err > tol {
        return Err(format!("position error {max_err:.3e} > {tol:.3e}"));
    }
    if map.iter().copied().collect::<HashSet<_>>().len() != map.len() {
        return Err("two points matched one".into());
    }
    let fb: HashSet<Vec<usize>> = (0..b.num_faces())
        .map(|i| canonical_face(&b.face(i).iter().map(|&x| x as usize).collect::<Vec<_>>()))
        .collect();
    for i in 0..a.num_faces() {
        let f: Vec<usize> = a.face(i).iter().map(|&x| map[x as usize]).collect();
        if !fb.contains(&canonical_face(&f)) {
            return Err(format!("face {i} {:?} not in the reference", a.face(i)));
        }
    }
    // One-sided normals: every corner's normal against the reference corner with the same
    // point and face.
    let mut corner_of: HashMap<(usize, Vec<usize>), [f32; 3]> = HashMap::new();
    for i in 0..b.num_faces() {
        let f: Vec<usize> = b.face(i).iter().map(|&x| x as usize).collect();
        let base = b.face_offsets()[i] as usize;
        for (k, &v) in f.iter().enumerate() {
            corner_of.insert((v, canonical_face(&f)), b.corner_normal(base + k));
        }
    }
    for i in 0..a.num_faces() {
        let f: Vec<usize> = a.face(i).iter().map(|&x| map[x as usize]).collect();
        let base = a.face_offsets()[i] as usize;
        for (k, &v) in f.iter().enumerate() {
            let want = dv(&corner_of[&(v, canonical_face(&f))]);
            let got = dv(&a.corner_normal(base + k));
            if want.length() > 0.5 && got.length() > 0.5 {
                let deg = want
                    .normalize()
                    .dot(got.normalize())
                    .clamp(-1.0, 1.0)
                    .acos();
                max_deg = max_deg.max(deg.to_degrees());
            }
        }
    }
    Ok((max_err, max_deg))
}

#[test]
fn loop_slates_equal_whole_mesh_refinement() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for (name, mesh) in loop_cages() {
        let (lo, hi) = mesh.bounds();
        let diag = (hi - lo).length() as f64;
        let deepest = if mesh.num_faces() > 1000 { 3 } else { 5 };
        for depth in 0..=deepest {
            let s = subdiv_slate::tessellate_tri(&mesh, depth).unwrap();
            let r = tessellate_uniform(&mesh, Scheme::Loop, depth).unwrap();
            match compare(&s, &r, 1e-6 * diag) {
                Ok((e, deg)) => {
                    eprintln!(
                        "{name} depth {depth}: max error {:.2e} x diag, normals within {deg:.4} deg",
                        e / diag
                    );
                    checked += 1;
                    if deg > 0.5 {
                        failures.push(format!("{name} depth {depth}: normals differ by {deg} deg"));
                    }
                }
                Err(e) => failures.push(format!("{name} depth {depth}: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked >= 50, "only {checked} comparisons");
}

#[test]
fn loop_slates_are_thread_count_independent() {
    for (name, mesh) in loop_cages() {
        let depth = if mesh.num_faces() > 1000 { 2 } else { 4 };
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| subdiv_slate::tessellate_tri(&mesh, depth).unwrap())
        };
        let one = run(1);
        for threads in [2, 3, 8] {
            assert!(
                one == run(threads),
                "{name}: {threads} threads differ from one"
            );
        }
    }
}

/// Every edge of a closed cage's tessellation has two triangles, of an open cage's one or two,
/// and the boundary edges are exactly the cage boundary's refinement.
#[test]
fn loop_slates_are_watertight() {
    for (name, mesh) in loop_cages() {
        let depth = if mesh.num_faces() > 1000 { 2 } else { 3 };
        let t = subdiv_slate::tessellate_tri(&mesh, depth).unwrap();
        let triangles: Vec<u32> = (0..t.num_faces())
            .flat_map(|i| t.face(i).to_vec())
            .collect();
        let open = indexed_open_edges(&name, &triangles);
        let holes = mesh.faces().any(|f| mesh.is_hole(f));
        let cage_open = mesh.edges().filter(|&e| mesh.is_boundary_edge(e)).count();
        if !holes {
            assert_eq!(open, cage_open << depth, "{name}: open edges");
        }
    }
}

/// Open cages under each boundary interpolation (`interpolateboundary 0`: faces at the boundary
/// are not drawn; 1 and 2 move the boundary corners differently) against the whole-mesh path.
#[test]
fn loop_slates_follow_boundary_interpolation() {
    let path = subdiv_tests::fixtures().join("reference/shapes/loop_saddle_edgecorner.obj");
    let text = std::fs::read_to_string(&path).unwrap();
    let text: String = text
        .lines()
        .filter(|l| !l.starts_with("t interpolateboundary"))
        .map(|l| format!("{l}\n"))
        .collect();
    for k in 0..=2 {
        let soup = subdiv_mesh::parse_obj(&format!("{text}t interpolateboundary 1/0/0 {k}\n"));
        let mesh = subdiv_mesh::Mesh::from_soup(&soup.unwrap()).unwrap();
        let (lo, hi) = mesh.bounds();
        let diag = (hi - lo).length() as f64;
        for depth in 0..=3 {
            let s = subdiv_slate::tessellate_tri(&mesh, depth).unwrap();
            let r = tessellate_uniform(&mesh, Scheme::Loop, depth).unwrap();
            assert!(s.num_faces() > 0 || k == 0);
            if let Err(e) = compare(&s, &r, 1e-6 * diag) {
                panic!("interpolateboundary {k} depth {depth}: {e}");
            }
        }
    }
}

/// The Loop slate against OpenSubdiv's limits (`fixtures/loop_slate/`, `ref_osd ... loop local`
/// at levels 1-3): Chaikin creases at a general corner, whose sides' limits read the corner's
/// sharpness at the table's level after the corner's own limit.
#[test]
fn chaikin_creases_at_a_corner_agree_with_opensubdiv() {
    use subdiv_tests::osd_compare::{Tessellator, assert_fixture_dir_agrees};
    assert_fixture_dir_agrees("loop_slate", 0.05, 6, |_| {
        vec![Tessellator::Uniform, Tessellator::Slate]
    });
}
