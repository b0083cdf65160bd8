//! Face-varying refinement (UVs) against OpenSubdiv 3.5: for every cage in
//! `fixtures/meshes/fvar` (UV seams, darts, junctions, a semi-sharp crease away from the seams),
//! every face-varying linear interpolation option and levels 1-3, uniform Catmull-Clark and
//! Loop refinement give the values of `PrimvarRefiner::InterpolateFaceVarying` at every corner
//! of every refined face, within 1e-5. References: `fixtures/reference/fvar/
//! <shape>.<scheme>.o<option>.L<level>.txt`, printed by `xtask/osd/ref_fvar.cpp`.

use subdiv_mesh::{FVarLinearInterpolation, Mesh, parse_obj};
use subdiv_rules::{Scheme, face_uvs, refine_uniform_levels};

use subdiv_tests::{fixture_files, fixtures};

/// Compares one reference file; returns the number of corners compared.
fn check(path: &std::path::Path) -> Result<usize, String> {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    let parts: Vec<&str> = name.split('.').collect();
    let [shape, scheme, option, level, "txt"] = parts[..] else {
        return Err(format!("{name}: not <shape>.<scheme>.o<k>.L<l>.txt"));
    };
    let scheme = match scheme {
        "catmark" => Scheme::CatmullClark,
        "loop" => Scheme::Loop,
        s => return Err(format!("{name}: scheme {s}")),
    };
    let option = FVarLinearInterpolation::from_tag(option[1..].parse().unwrap()).unwrap();
    let level: u8 = level[1..].parse().unwrap();
    let text =
        std::fs::read_to_string(fixtures().join(format!("meshes/fvar/{shape}.obj"))).unwrap();
    let mut soup = parse_obj(&text).map_err(|e| e.to_string())?;
    soup.options.fvar = option;
    let mesh = Mesh::from_soup(&soup).map_err(|e| e.to_string())?;
    let refined = refine_uniform_levels(&mesh, scheme, level).map_err(|e| e.to_string())?;
    let reference = std::fs::read_to_string(path).unwrap();
    let faces: Vec<Vec<f64>> = reference
        .lines()
        .filter(|l| l.starts_with("f "))
        .map(|l| l[2..].split(' ').map(|x| x.parse().unwrap()).collect())
        .collect();
    if faces.len() != refined.num_faces() {
        return Err(format!(
            "{name}: {} faces, OpenSubdiv has {}",
            refined.num_faces(),
            faces.len()
        ));
    }
    // Child faces of each cage face are contiguous in both, but OpenSubdiv rotates the children
    // of quads (and the middle child of a triangle) so that their corners follow the parent's,
    // which also reorders their descendants: match each face to an unused reference face of
    // the same cage face, up to rotation.
    let got: Vec<Vec<glam::Vec2>> = refined
        .faces()
        .map(|f| face_uvs(&refined, f).unwrap_or_default())
        .collect();
    let same = |g: &[glam::Vec2], w: &[f64], r: usize| {
        let n = g.len();
        w.len() == 2 * n
            && (0..n).all(|k| {
                let uv = g[(k + r) % n];
                (f64::from(uv.x) - w[2 * k]).abs() <= 1e-5
                    && (f64::from(uv.y) - w[2 * k + 1]).abs() <= 1e-5
            })
    };
    let per = 4usize.pow(u32::from(level) - 1);
    let mut start = 0;
    let mut corners = 0;
    for f in mesh.faces() {
        let block = match scheme {
            Scheme::CatmullClark => mesh.face_size(f) * per,
            Scheme::Loop => 4 * per,
        };
        let mut used = vec![false; block];
        for (i, g) in got[start..start + block].iter().enumerate() {
            let hit = (0..block)
                .find(|&j| !used[j] && (0..g.len()).any(|r| same(g, &faces[start + j], r)));
            match hit {
                Some(j) => used[j] = true,
                None => {
                    return Err(format!(
                        "{name}: face {}: {g:?} is not among OpenSubdiv's faces of cage face {}",
                        start + i,
                        f.0
                    ));
                }
            }
            corners += g.len();
        }
        start += block;
    }
    Ok(corners)
}

#[test]
fn face_varying_refinement_matches_opensubdiv() {
    let files = fixture_files("reference/fvar", "txt");
    assert_eq!(
        files.len(),
        90,
        "5 shape/scheme pairs x 6 options x 3 levels"
    );
    let mut failures = Vec::new();
    let mut corners = 0;
    for path in &files {
        match check(path) {
            Ok(n) => corners += n,
            Err(e) => failures.push(e),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} differ:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
    assert!(corners > 10_000, "{corners}");
}
