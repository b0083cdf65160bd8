//! The slate tessellator against the whole-mesh reference path and OpenSubdiv.

use std::collections::HashSet;

use glam::DVec3;
use subdiv_mesh::Mesh;
use subdiv_rules::{LimitMesh, Scheme, tessellate_uniform};
use subdiv_tests::{PointGrid, canonical_face};

fn cc_cages() -> Vec<(String, Mesh)> {
    subdiv_tests::catmull_clark_cages()
}

fn dv(p: &[f32; 3]) -> DVec3 {
    glam::Vec3::from(*p).as_dvec3()
}

/// Compares two tessellations as point sets with the same faces; returns the max position error
/// and max normal angle (degrees, at points with both normals nonzero).
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
    let mut max_err = 0.0f64;
    let mut max_deg = 0.0f64;
    for (i, p) in a.positions().iter().enumerate() {
        let (j, d) = grid.nearest(dv(p));
        map[i] = j;
        max_err = max_err.max(d);
        let (na, nb) = (dv(&a.normals()[i]), dv(&b.normals()[j]));
        if na.length() > 0.5 && nb.length() > 0.5 {
            max_deg = max_deg.max(
                na.normalize()
                    .dot(nb.normalize())
                    .clamp(-1.0, 1.0)
                    .acos()
                    .to_degrees(),
            );
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
    Ok((max_err, max_deg))
}

#[test]
fn slates_equal_whole_mesh_refinement() {
    let mut failures = Vec::new();
    for (name, mesh) in cc_cages() {
        let (lo, hi) = mesh.bounds();
        let diag = (hi - lo).length() as f64;
        for depth in 0..=3 {
            let s = subdiv_slate::tessellate(&mesh, depth).unwrap();
            let r = tessellate_uniform(&mesh, Scheme::CatmullClark, depth).unwrap();
            match compare(&s, &r, 1e-6 * diag) {
                Ok((e, deg)) => {
                    eprintln!(
                        "{name} depth {depth}: max error {:.2e} x diag, normals within {deg:.4} deg",
                        e / diag
                    );
                    if deg > 0.5 {
                        failures.push(format!("{name} depth {depth}: normals differ by {deg} deg"));
                    }
                }
                Err(e) => failures.push(format!("{name} depth {depth}: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Deeper levels (4 to 6; 6 is past the default `max_depth` of 5, so the slates grow) on the small
/// creased, boundary and Chaikin cages: the band
/// invariant of the general step (checked by debug assertions), the separable regular rules and
/// the per-configuration limit stencils still give the whole-mesh reference's surface.
#[test]
fn deep_slates_equal_whole_mesh_refinement() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for (name, mesh) in cc_cages() {
        let creased = mesh.edges().any(|e| mesh.edge_sharpness(e) > 0.0);
        let open = mesh.edges().any(|e| mesh.is_boundary_edge(e));
        if mesh.num_faces() > 40 || !(creased || open) {
            continue;
        }
        let (lo, hi) = mesh.bounds();
        let diag = (hi - lo).length() as f64;
        for depth in 4..=6 {
            let s = subdiv_slate::tessellate(&mesh, depth).unwrap();
            let r = tessellate_uniform(&mesh, Scheme::CatmullClark, depth).unwrap();
            // Both paths round in f32 at every level: at depth 4 their difference reaches
            // 1.01e-6 x diag on catmark_flap (the same before the band and stencil changes), and
            // 1.13e-6 at depth 6.
            match compare(&s, &r, 2e-6 * diag) {
                Ok((_, deg)) if deg > 0.5 => {
                    failures.push(format!("{name} depth {depth}: normals differ by {deg} deg"))
                }
                Ok((e, deg)) => {
                    eprintln!(
                        "{name} depth {depth}: max error {:.2e} x diag, normals within {deg:.4} deg",
                        e / diag
                    );
                    checked += 1;
                }
                Err(e) => failures.push(format!("{name} depth {depth}: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked >= 15, "only {checked} deep comparisons");
}
