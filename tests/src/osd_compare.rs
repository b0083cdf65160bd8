//! Comparing a subdiv tessellation with an OpenSubdiv reference limit file (the format of
//! `fixtures/reference/OSD_REFERENCE_FORMAT.md`, as `xtask/osd/ref_osd.cpp` prints it): equal
//! vertex and face counts, the same faces with the same orientation, positions within a
//! tolerance relative to the cage's bounding-box diagonal, normals within an angle where the
//! surface is smooth. Used by `tests/tests/reference.rs` (the stored fixtures) and by
//! `cargo xtask fuzz-osd` (random cages).
//!
//! Semi-sharp creases: the reference positions are OpenSubdiv's limit from the level where every
//! crease has run out (`exact_from_level`), subdiv's are exact at any level, so both compare
//! directly.

use std::collections::HashSet;

use glam::DVec3;
use subdiv_mesh::{Mesh, VertexId};
use subdiv_rules::{
    Depth, LimitMesh, Scheme, bilinear_patches, inside_one_patch, refine_uniform_levels,
    tessellate_uniform,
};

use crate::{PointGrid, Reference, canonical_face};

/// Which subdiv tessellator to compare.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tessellator {
    /// `subdiv_rules::tessellate_uniform` (the whole-mesh path; Catmull-Clark and Loop).
    Uniform,
    /// The slate tessellators: `subdiv_slate::tessellate` (Catmull-Clark) or
    /// `subdiv_slate::tessellate_tri` (Loop), by the reference's scheme.
    Slate,
}

/// The largest differences found.
#[derive(Clone, Copy, Debug, Default)]
pub struct Outcome {
    /// Largest position difference over the cage's bounding-box diagonal.
    pub max_pos_err: f64,
    /// Largest normal difference (degrees) where the surface is smooth.
    pub max_normal_deg: f64,
    /// Number of normals compared.
    pub smooth_normals: usize,
}

/// The scheme a reference file was computed with.
pub fn reference_scheme(reference: &Reference) -> Scheme {
    match reference.header.get("scheme").map(String::as_str) {
        Some("loop") => Scheme::Loop,
        Some("bilinear") => Scheme::Bilinear,
        _ => Scheme::CatmullClark,
    }
}

/// Compares `which` tessellation of `mesh` at `level` with `reference`: positions within
/// `1e-5` x the bounding-box diagonal, normals within `normal_deg` degrees where smooth.
pub fn compare(
    mesh: &Mesh,
    level: Depth,
    reference: &Reference,
    which: Tessellator,
    normal_deg: f64,
) -> Result<Outcome, String> {
    let scheme = reference_scheme(reference);
    let t = match which {
        Tessellator::Slate => match scheme {
            Scheme::CatmullClark => subdiv_slate::tessellate(mesh, level),
            Scheme::Loop => subdiv_slate::tessellate_tri(mesh, level),
            Scheme::Bilinear => subdiv_slate::tessellate_bilinear(mesh, level),
        }
        .map_err(|e| e.to_string())?,
        Tessellator::Uniform => {
            tessellate_uniform(mesh, scheme, level).map_err(|e| e.to_string())?
        }
    };
    let (lo, hi) = mesh.bounds();
    let diag = (hi - lo).length() as f64;
    let tol = 1e-5 * diag;
    let all = dvec(&t);
    // A non-manifold cage is refined as manifold pieces whose copies of a vertex coincide
    // (`PolygonSoup::split_nonmanifold`): weld them where ours has more points than OpenSubdiv.
    let weld = if all.len() > reference.num("V") {
        Weld::new(&all, 1e-6 * diag)
    } else {
        Weld::identity(all.len())
    };
    if weld.kept.len() != reference.num("V") || t.num_faces() != reference.num("F") {
        return Err(format!(
            "counts: ours V={} (welded {}) F={}, reference V={} F={}",
            t.positions().len(),
            weld.kept.len(),
            t.num_faces(),
            reference.num("V"),
            reference.num("F")
        ));
    }
    let ours: Vec<DVec3> = weld.kept.iter().map(|&i| all[i]).collect();
    let (map, max_err) = match_points(&ours, reference, tol)?;
    check_faces(&t, reference, &map, &weld.to)?;
    // Reference vertex -> our (unwelded) vertex.
    let map: Vec<usize> = map.iter().map(|&k| weld.kept[k]).collect();
    let (max_deg, n_smooth) =
        check_normals(which, mesh, scheme, level, &t, reference, &map, normal_deg)?;
    Ok(Outcome {
        max_pos_err: max_err / diag,
        max_normal_deg: max_deg,
        smooth_normals: n_smooth,
    })
}

fn dvec(t: &LimitMesh) -> Vec<DVec3> {
    t.positions()
        .iter()
        .map(|p| glam::Vec3::from(*p).as_dvec3())
        .collect()
}

/// Maps every reference vertex to ours: by index for the cage vertices, by position otherwise.
/// Returns the map and the largest distance.
fn match_points(
    ours: &[DVec3],
    reference: &Reference,
    tol: f64,
) -> Result<(Vec<usize>, f64), String> {
    let base = reference.num("base_verts");
    let grid = PointGrid::new(ours, (tol * 100.0).max(1e-9));
    let mut map = vec![0usize; reference.positions.len()];
    let mut max_err = 0.0f64;
    let mut worst = 0;
    for (i, p) in reference.positions.iter().enumerate() {
        let (j, d) = if i < base && i < ours.len() {
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
    Ok((map, max_err))
}

/// Points welded within a distance: `to[i]` is the kept point standing for point `i`, `kept`
/// the kept points' indices (the first of each cluster, in order).
struct Weld {
    to: Vec<usize>,
    kept: Vec<usize>,
}

impl Weld {
    fn identity(n: usize) -> Weld {
        Weld {
            to: (0..n).collect(),
            kept: (0..n).collect(),
        }
    }

    fn new(points: &[DVec3], tol: f64) -> Weld {
        let cell = tol.max(1e-12);
        let key = |p: DVec3| {
            let k = |x: f64| (x / cell).floor() as i64;
            (k(p.x), k(p.y), k(p.z))
        };
        let mut cells: std::collections::HashMap<(i64, i64, i64), Vec<usize>> =
            std::collections::HashMap::new();
        let mut w = Weld {
            to: Vec::with_capacity(points.len()),
            kept: Vec::new(),
        };
        for (i, &p) in points.iter().enumerate() {
            let (x, y, z) = key(p);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        for &k in cells.get(&(x + dx, y + dy, z + dz)).into_iter().flatten() {
                            if (points[w.kept[k]] - p).length() <= tol {
                                found = Some(k);
                                break 'search;
                            }
                        }
                    }
                }
            }
            let k = found.unwrap_or_else(|| {
                w.kept.push(i);
                cells.entry((x, y, z)).or_default().push(w.kept.len() - 1);
                w.kept.len() - 1
            });
            w.to.push(k);
        }
        w
    }
}

/// Same faces, same orientation (ours through `weld`: our vertex -> welded index).
fn check_faces(
    t: &LimitMesh,
    reference: &Reference,
    map: &[usize],
    weld: &[usize],
) -> Result<(), String> {
    let our_faces: HashSet<Vec<usize>> = (0..t.num_faces())
        .map(|i| {
            canonical_face(
                &t.face(i)
                    .iter()
                    .map(|&x| weld[x as usize])
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    for f in &reference.faces {
        let mapped: Vec<usize> = f.iter().map(|&i| map[i]).collect();
        if !our_faces.contains(&canonical_face(&mapped)) {
            return Err(format!(
                "reference face {f:?} (ours {mapped:?}) is missing or flipped"
            ));
        }
    }
    Ok(())
}

/// Normals where the limit surface is smooth: no infinitely sharp edge or vertex at the point
/// (a property of the refined mesh's vertex, found by position: the slate output numbers its
/// vertices differently). Returns the largest difference and the number compared.
#[allow(clippy::too_many_arguments)]
fn check_normals(
    which: Tessellator,
    mesh: &Mesh,
    scheme: Scheme,
    level: Depth,
    t: &LimitMesh,
    reference: &Reference,
    map: &[usize],
    normal_deg: f64,
) -> Result<(f64, usize), String> {
    let refined = refine_uniform_levels(mesh, scheme, level).map_err(|e| e.to_string())?;
    // The whole-mesh tessellation numbers its vertices like `refined` (`t` itself when it is
    // that tessellation).
    let uniform;
    let limit_ref = if which == Tessellator::Uniform {
        t
    } else {
        uniform = tessellate_uniform(mesh, scheme, level).map_err(|e| e.to_string())?;
        &uniform
    };
    let (lo, hi) = mesh.bounds();
    let tol = 1e-5 * (hi - lo).length() as f64;
    let ref_grid = PointGrid::new(&dvec(limit_ref), (tol * 100.0).max(1e-9));
    // Bilinear: smooth inside a patch, kinked along the patches' edges.
    let patches = (scheme == Scheme::Bilinear).then(|| bilinear_patches(mesh, level));
    let mut max_deg = 0.0f64;
    let mut n_smooth = 0;
    for (i, rn) in reference.normals.iter().enumerate() {
        let rv = VertexId(ref_grid.nearest(reference.positions[i]).0 as u32);
        let smooth = match &patches {
            Some(p) => inside_one_patch(&refined, p, rv),
            None => is_smooth_point(&refined, rv),
        };
        if !smooth {
            continue;
        }
        n_smooth += 1;
        let on = glam::Vec3::from(t.normals()[map[i]]).as_dvec3();
        // Fully degenerate tangents: OpenSubdiv's du x dv and subdiv's normal are both zero
        // (seed 13 cage 16024), which is agreement; one zero normal alone is not.
        if on == DVec3::ZERO && *rn == DVec3::ZERO {
            continue;
        }
        let deg = on.dot(rn.normalize()).clamp(-1.0, 1.0).acos().to_degrees();
        max_deg = max_deg.max(deg);
        if deg > normal_deg || deg.is_nan() {
            return Err(format!(
                "normal at reference vertex {i} {:?} off by {deg:.4} degrees: ours {on:?}, reference {rn:?}",
                reference.positions[i]
            ));
        }
    }
    Ok((max_deg, n_smooth))
}

/// No infinitely sharp edge or vertex at `v` of a refined mesh (nor a crease copy).
pub fn is_smooth_point(m: &Mesh, v: VertexId) -> bool {
    // A crease copy lies on the whole vertex's crease, whichever edges its ring holds.
    m.crease_ends(v).is_none()
        && m.vertex_sharpness(v) < subdiv_mesh::SHARPNESS_INFINITE
        && !m.is_isolated(v)
        && m.outgoing(v)
            .all(|h| m.edge_sharpness(h.edge()) < subdiv_mesh::SHARPNESS_INFINITE)
}

/// Compares every reference `fixtures/<dir>/<cage>.L<level>.txt` with `<cage>.obj` read by
/// `read_obj`, through the tessellators `paths(cage text)` names, as fuzz-osd does (normals
/// within `normal_deg`). Panics listing every disagreement, or when fewer than `min_checks`
/// comparisons ran (so a fixture directory cannot silently empty).
pub fn assert_fixture_dir_agrees(
    dir: &str,
    normal_deg: f64,
    min_checks: usize,
    paths: impl Fn(&str) -> Vec<Tessellator>,
) {
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in crate::fixture_files(dir, "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        let (cage, lv) = name.rsplit_once(".L").unwrap();
        let level: Depth = lv.parse().unwrap();
        let path = crate::fixtures().join(dir).join(format!("{cage}.obj"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{cage}: {e}"));
        let mesh = subdiv_mesh::read_obj(&path).unwrap_or_else(|e| panic!("{cage}: {e}"));
        let reference = Reference::read(&file);
        for which in paths(&text) {
            checked += 1;
            if let Err(e) = compare(&mesh, level, &reference, which, normal_deg) {
                failures.push(format!("{name} ({which:?}): {e}"));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {checked} checks disagree with OpenSubdiv:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(checked >= min_checks, "only {checked} checks");
}
