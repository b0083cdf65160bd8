//! Uniform limit tessellations against OpenSubdiv 3.5 reference limit surfaces, for every
//! reference shape at levels 1-3: equal vertex and face counts, the same faces, positions within
//! 1e-5 of the cage's bounding-box diagonal, normals within 0.5 degrees where the surface is
//! smooth (no infinitely sharp edge or vertex at the point).

use std::collections::HashSet;

use glam::DVec3;
use subdiv_mesh::{Mesh, VertexId, read_obj};
use subdiv_rules::{Scheme, refine_uniform_levels, tessellate_uniform};
use subdiv_tests::{PointGrid, Reference, canonical_face, fixture_files, fixtures};

struct Outcome {
    max_pos_err: f64,
    max_normal_deg: f64,
    smooth_normals: usize,
}

fn check(shape: &str, level: subdiv_rules::Depth) -> Result<Outcome, String> {
    check_with(shape, level, false)
}

/// Catmull-Clark shapes again, through the slate tessellator.
fn check_slate(shape: &str, level: subdiv_rules::Depth) -> Result<Outcome, String> {
    check_with(shape, level, true)
}

fn check_with(shape: &str, level: subdiv_rules::Depth, slates: bool) -> Result<Outcome, String> {
    let cage_path = fixtures()
        .join("reference/shapes")
        .join(format!("{shape}.obj"));
    let reference =
        Reference::read(&fixtures().join(format!("reference/limit/{shape}.L{level}.txt")));
    let mesh = read_obj(&cage_path).map_err(|e| e.to_string())?;
    let scheme = if reference.header["scheme"] == "loop" {
        Scheme::Loop
    } else {
        Scheme::CatmullClark
    };
    let t = if slates {
        subdiv_slate::tessellate(&mesh, level).map_err(|e| e.to_string())?
    } else {
        tessellate_uniform(&mesh, scheme, level).map_err(|e| e.to_string())?
    };
    let (lo, hi) = mesh.bounds();
    let diag = (hi - lo).length() as f64;
    let tol = 1e-5 * diag;

    if t.positions.len() != reference.num("V") || t.num_faces() != reference.num("F") {
        return Err(format!(
            "counts: ours V={} F={}, reference V={} F={}",
            t.positions.len(),
            t.num_faces(),
            reference.num("V"),
            reference.num("F")
        ));
    }
    let ours: Vec<DVec3> = t
        .positions
        .iter()
        .map(|p| glam::Vec3::from(*p).as_dvec3())
        .collect();
    let base = reference.num("base_verts");
    let grid = PointGrid::new(&ours, (tol * 100.0).max(1e-9));

    // Map every reference vertex to ours: by index for the cage vertices, by position otherwise.
    let mut map = vec![0usize; reference.positions.len()];
    let mut max_err = 0.0f64;
    let mut worst = 0;
    for (i, p) in reference.positions.iter().enumerate() {
        let (j, d) = if i < base {
            (i, (ours[i] - *p).length())
        } else {
            grid.nearest(*p)
        };
        map[i] = j;
        if d > max_err {
            max_err = d;
            worst = i;
        }
    }
    if max_err > tol {
        return Err(format!(
            "position error {:.3e} (tolerance {:.3e}) at reference vertex {worst} {:?}, ours {:?}",
            max_err, tol, reference.positions[worst], ours[map[worst]]
        ));
    }
    let distinct: HashSet<usize> = map.iter().copied().collect();
    if distinct.len() != map.len() {
        return Err("two reference vertices matched the same vertex of ours".into());
    }

    // Same faces, same orientation.
    let our_faces: HashSet<Vec<usize>> = (0..t.num_faces())
        .map(|i| canonical_face(&t.face(i).iter().map(|&x| x as usize).collect::<Vec<_>>()))
        .collect();
    for f in &reference.faces {
        let mapped: Vec<usize> = f.iter().map(|&i| map[i]).collect();
        if !our_faces.contains(&canonical_face(&mapped)) {
            return Err(format!(
                "reference face {f:?} (ours {mapped:?}) is missing or flipped"
            ));
        }
    }

    // Normals where the limit surface is smooth: no infinitely sharp edge or vertex at the point.
    let refined = refine_uniform_levels(&mesh, scheme, level).map_err(|e| e.to_string())?;
    // Smoothness is a property of the refined mesh's vertex, found by position (the slate
    // output numbers its vertices differently).
    let limit_ref = tessellate_uniform(&mesh, scheme, level).map_err(|e| e.to_string())?;
    let limit_pts: Vec<DVec3> = limit_ref
        .positions
        .iter()
        .map(|p| glam::Vec3::from(*p).as_dvec3())
        .collect();
    let ref_grid = PointGrid::new(&limit_pts, (tol * 100.0).max(1e-9));
    let mut max_deg = 0.0f64;
    let mut n_smooth = 0;
    for (i, rn) in reference.normals.iter().enumerate() {
        let v = VertexId(map[i] as u32);
        let rv = VertexId(ref_grid.nearest(reference.positions[i]).0 as u32);
        if !is_smooth_point(&refined, rv) {
            continue;
        }
        n_smooth += 1;
        let on = glam::Vec3::from(t.normals[v.idx()]).as_dvec3();
        let deg = on.dot(rn.normalize()).clamp(-1.0, 1.0).acos().to_degrees();
        if deg > max_deg {
            max_deg = deg;
        }
        if deg > 0.5 {
            return Err(format!(
                "normal at reference vertex {i} off by {deg:.3} degrees: ours {on:?}, reference {rn:?}"
            ));
        }
    }
    Ok(Outcome {
        max_pos_err: max_err / diag,
        max_normal_deg: max_deg,
        smooth_normals: n_smooth,
    })
}

fn is_smooth_point(m: &Mesh, v: VertexId) -> bool {
    m.vertex_sharpness(v) < subdiv_mesh::SHARPNESS_INFINITE
        && !m.is_isolated(v)
        && m.outgoing(v)
            .all(|h| m.edge_sharpness(h.edge()) < subdiv_mesh::SHARPNESS_INFINITE)
}

#[test]
fn every_reference_shape_matches_opensubdiv() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in fixture_files("reference/limit", "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        let (shape, lv) = name.rsplit_once(".L").unwrap();
        let level: subdiv_rules::Depth = lv.parse().unwrap();
        match check(shape, level) {
            Ok(o) => {
                checked += 1;
                eprintln!(
                    "{name}: max position error {:.2e} x diag, {} smooth normals within {:.4} deg",
                    o.max_pos_err, o.smooth_normals, o.max_normal_deg
                );
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} reference checks failed:\n{}",
        failures.len(),
        checked + failures.len(),
        failures.join("\n")
    );
    assert!(checked >= 90, "only {checked} reference files checked");
}

#[test]
fn slate_tessellation_matches_opensubdiv() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in fixture_files("reference/limit", "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        if !name.starts_with("catmark_") {
            continue;
        }
        let (shape, lv) = name.rsplit_once(".L").unwrap();
        match check_slate(shape, lv.parse().unwrap()) {
            Ok(o) => {
                checked += 1;
                eprintln!(
                    "slate {name}: max position error {:.2e} x diag, normals within {:.4} deg",
                    o.max_pos_err, o.max_normal_deg
                );
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked >= 60, "only {checked} checked");
}
