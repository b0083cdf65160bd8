//! Face-varying limit values (UVs) on the uniform slates against the whole-mesh reference path
//! (`tessellate_uniform`, whose UVs are `limit_face_varying` of the refined mesh, checked
//! against OpenSubdiv in `osd_fvar.rs`): every UV cage of `fixtures/meshes/fvar` under every
//! face-varying option, Catmull-Clark slates (quads, and triangles through level-1 units),
//! triangular Loop slates and bilinear patches (linear whatever the option), depths 0-4. Each slate face is matched to its reference face by
//! position and every corner's UV compared (seams: a corner takes its own face's side). The
//! UVs are the same for 1 and 2 threads.

use std::collections::HashMap;

use glam::DVec3;
use subdiv_mesh::{FVarLinearInterpolation, Mesh, parse_obj};
use subdiv_rules::{LimitMesh, Scheme, tessellate_uniform};
use subdiv_tests::{PointGrid, canonical_face, fixtures};

/// The UV cages with every option, and the schemes each takes.
fn uv_cages() -> Vec<(String, Mesh, Vec<Scheme>)> {
    let mut out = Vec::new();
    for (shape, schemes) in [
        ("cube_uv", vec![Scheme::CatmullClark, Scheme::Bilinear]),
        ("grid_seam", vec![Scheme::CatmullClark, Scheme::Bilinear]),
        ("grid_seam_crease", vec![Scheme::CatmullClark]),
        (
            "tri_seam",
            vec![Scheme::CatmullClark, Scheme::Loop, Scheme::Bilinear],
        ),
    ] {
        let path = fixtures().join(format!("meshes/fvar/{shape}.obj"));
        let text = std::fs::read_to_string(path).unwrap();
        for option in FVarLinearInterpolation::ALL {
            let mut soup = parse_obj(&text).unwrap();
            soup.options.fvar = option;
            let mesh = Mesh::from_soup(&soup).unwrap();
            out.push((format!("{shape} {}", option.name()), mesh, schemes.clone()));
        }
    }
    out
}

fn slates(mesh: &Mesh, scheme: Scheme, depth: u8) -> LimitMesh {
    match scheme {
        Scheme::CatmullClark => subdiv_slate::tessellate(mesh, depth).unwrap(),
        Scheme::Loop => subdiv_slate::tessellate_tri(mesh, depth).unwrap(),
        Scheme::Bilinear => subdiv_slate::tessellate_bilinear(mesh, depth).unwrap(),
    }
}

/// Compares the UV of every corner of `a` with the corner at the same point of the same face
/// of `b`; returns the number of corners compared.
fn compare_uvs(a: &LimitMesh, b: &LimitMesh, tol: f64) -> Result<usize, String> {
    if a.uv_indices().len() != a.face_indices().len()
        || b.uv_indices().len() != b.face_indices().len()
    {
        return Err("UVs missing".into());
    }
    let dv = |p: &[f32; 3]| glam::Vec3::from(*p).as_dvec3();
    let pb: Vec<DVec3> = b.positions().iter().map(dv).collect();
    let grid = PointGrid::new(&pb, 1e-3);
    let map: Vec<usize> = a
        .positions()
        .iter()
        .map(|p| grid.nearest(dv(p)).0)
        .collect();
    let faces: HashMap<Vec<usize>, usize> = (0..b.num_faces())
        .map(|i| {
            let f: Vec<usize> = b.face(i).iter().map(|&x| x as usize).collect();
            (canonical_face(&f), i)
        })
        .collect();
    let uv = |m: &LimitMesh, c: usize| m.uvs()[m.uv_indices()[c] as usize];
    let mut corners = 0;
    for i in 0..a.num_faces() {
        let f: Vec<usize> = a.face(i).iter().map(|&x| map[x as usize]).collect();
        let &j = faces
            .get(&canonical_face(&f))
            .ok_or_else(|| format!("face {i} not in the reference"))?;
        let (sa, sb) = (a.face_offsets()[i] as usize, b.face_offsets()[j] as usize);
        for (k, &v) in f.iter().enumerate() {
            let kb = b.face(j).iter().position(|&x| x as usize == v).unwrap();
            let (ua, ub) = (uv(a, sa + k), uv(b, sb + kb));
            let d = f64::from((ua[0] - ub[0]).abs().max((ua[1] - ub[1]).abs()));
            if d > tol {
                return Err(format!("face {i} corner {k}: {ua:?}, reference {ub:?}"));
            }
            corners += 1;
        }
    }
    Ok(corners)
}

#[test]
fn slate_uvs_equal_the_whole_mesh_limit_uvs() {
    let mut failures = Vec::new();
    let mut corners = 0;
    for (name, mesh, schemes) in uv_cages() {
        for scheme in schemes {
            for depth in 0..=4 {
                let s = slates(&mesh, scheme, depth);
                let r = tessellate_uniform(&mesh, scheme, depth).unwrap();
                match compare_uvs(&s, &r, 1e-5) {
                    Ok(n) => corners += n,
                    Err(e) => failures.push(format!("{name} {scheme:?} depth {depth}: {e}")),
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(corners > 100_000, "{corners}");
}

#[test]
fn slate_uvs_do_not_depend_on_the_thread_count() {
    for (name, mesh, schemes) in uv_cages().into_iter().step_by(5) {
        for scheme in schemes {
            let run = |threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| slates(&mesh, scheme, 3))
            };
            let (one, two) = (run(1), run(2));
            assert!(!one.uvs().is_empty(), "{name}");
            assert_eq!(one, two, "{name} {scheme:?}");
        }
    }
}

#[test]
fn limit_uvs_are_not_the_refined_uvs() {
    // The limit of a UV map is not its refined values: the test above could not pass with
    // the refined values copied on either side.
    let (_, mesh, _) = uv_cages().into_iter().nth(1).unwrap(); // cube_uv cornersOnly
    let refined = subdiv_rules::refine_uniform_levels(&mesh, Scheme::CatmullClark, 2).unwrap();
    let limit = subdiv_rules::limit_face_varying(&refined, Scheme::CatmullClark).unwrap();
    let fv = refined.uv().unwrap();
    let moved = (0..fv.indices.len())
        .filter(|&c| (fv.corner(c) - limit.corner(c)).length() > 1e-4)
        .count();
    assert!(moved > fv.indices.len() / 10, "{moved}");
}
