//! Face-varying refinement against OpenSubdiv: the reference format of
//! `xtask/osd/ref_fvar.cpp`, the comparison (shared by `tests/tests/osd_fvar.rs` and
//! `cargo xtask fuzz-osd`) and UV seams for random cages.

use std::fmt::Write as _;

use subdiv_mesh::{FaceVarying, Mesh};
use subdiv_rules::{Depth, Scheme, face_uvs};

use crate::fuzz::Rng;
use crate::osd_cage::OsdCage;

/// The corner values of every face of a `ref_fvar` output (`f u0 v0 u1 v1 ...` lines).
pub fn parse_fvar(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter_map(|l| l.strip_prefix("f "))
        .map(|l| l.split(' ').filter_map(|x| x.parse().ok()).collect())
        .collect()
}

/// How far a value may be from OpenSubdiv's `w`: 1e-5, or 1e-6 of `w`'s magnitude where that
/// is larger (both refine in `f32`, in different orders: a few units in the last place of a
/// large value).
pub fn value_tolerance(w: f64) -> f64 {
    1e-5f64.max(1e-6 * w.abs())
}

/// Compares the UVs of `refined` (the level-`level` uniform refinement of `cage`) with
/// OpenSubdiv's `faces`, within [`value_tolerance`]; returns the number of corners compared.
pub fn compare_fvar(
    cage: &Mesh,
    scheme: Scheme,
    level: Depth,
    refined: &Mesh,
    faces: &[Vec<f64>],
) -> Result<usize, String> {
    let got: Vec<Vec<glam::Vec2>> = refined
        .faces()
        .map(|f| face_uvs(refined, f).unwrap_or_default())
        .collect();
    compare_corner_values(cage, scheme, level, &got, faces)
}

/// Compares the face-varying values `uvs` of `refined`'s corners (e.g. its limit values,
/// [`subdiv_rules::limit_face_varying`]) with OpenSubdiv's `faces`, as [`compare_fvar`].
pub fn compare_fvar_values(
    cage: &Mesh,
    scheme: Scheme,
    level: Depth,
    refined: &Mesh,
    uvs: &FaceVarying,
    faces: &[Vec<f64>],
) -> Result<usize, String> {
    let (offsets, _) = refined.face_lists();
    let got: Vec<Vec<glam::Vec2>> = refined
        .faces()
        .map(|f| {
            (offsets[f.idx()]..offsets[f.idx() + 1])
                .map(|c| uvs.corner(c as usize))
                .collect()
        })
        .collect();
    compare_corner_values(cage, scheme, level, &got, faces)
}

/// The comparison of [`compare_fvar`] on the corner values `got` of every refined face.
///
/// Child faces of each cage face are contiguous in both, but OpenSubdiv rotates the children
/// of quads (and the middle child of a triangle) so that their corners follow the parent's,
/// which also reorders their descendants: each face is matched to an unused reference face of
/// the same cage face, up to rotation.
fn compare_corner_values(
    cage: &Mesh,
    scheme: Scheme,
    level: Depth,
    got: &[Vec<glam::Vec2>],
    faces: &[Vec<f64>],
) -> Result<usize, String> {
    let mesh = cage;
    if faces.len() != got.len() {
        return Err(format!(
            "{} faces, OpenSubdiv has {}",
            got.len(),
            faces.len()
        ));
    }
    // The largest coordinate difference of `g` rotated by `r` from `w`, in units of
    // `VALUE_TOLERANCE`.
    let apart = |g: &[glam::Vec2], w: &[f64], r: usize| {
        let n = g.len();
        if w.len() != 2 * n {
            return f64::INFINITY;
        }
        (0..n)
            .flat_map(|k| {
                let uv = g[(k + r) % n];
                [(uv.x, w[2 * k]), (uv.y, w[2 * k + 1])]
            })
            .map(|(a, b)| (f64::from(a) - b).abs() / value_tolerance(b))
            .fold(0.0, f64::max)
    };
    let same = |g: &[glam::Vec2], w: &[f64], r: usize| apart(g, w, r) <= 1.0;
    let per = 4usize.pow(u32::from(level) - 1);
    let mut start = 0;
    let mut corners = 0;
    for f in mesh.faces() {
        let block = match scheme {
            Scheme::CatmullClark | Scheme::Bilinear => mesh.face_size(f) * per,
            Scheme::Loop => 4 * per,
        };
        let mut used = vec![false; block];
        for (i, g) in got[start..start + block].iter().enumerate() {
            let hit = (0..block)
                .find(|&j| !used[j] && (0..g.len()).any(|r| same(g, &faces[start + j], r)));
            match hit {
                Some(j) => used[j] = true,
                None => {
                    let nearest = (0..block)
                        .flat_map(|j| (0..g.len()).map(move |r| (j, r)))
                        .map(|(j, r)| apart(g, &faces[start + j], r))
                        .fold(f64::INFINITY, f64::min);
                    return Err(format!(
                        "face {}: {g:?} is not among OpenSubdiv's faces of cage face {} \
                         (the nearest is {nearest:.1} tolerances away)",
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

/// The cage's OBJ text with UVs: each face is put in one of three charts at random (from
/// `seed`), a vertex gets one value per chart it is used in (so chart borders are seams, with
/// corners, darts and junctions), and a random face-varying option (`t
/// facevaryinginterpolateboundary`).
pub fn cage_obj_with_uvs(cage: &OsdCage, seed: u64) -> String {
    let mut rng = Rng::for_case(seed, 0xf1a7);
    let nv = cage.positions.len();
    let mut s: String = cage
        .to_obj()
        .lines()
        .filter(|l| !l.starts_with("f "))
        .map(|l| format!("{l}\n"))
        .collect();
    for chart in 0..3 {
        for p in &cage.positions {
            let _ = writeln!(
                s,
                "vt {} {}",
                p[0] + p[2] * 0.5 + 4.0 * chart as f64,
                p[1] - p[2] * 0.25
            );
        }
    }
    for f in &cage.faces {
        let chart = (rng.next_u64() % 3) as usize;
        s.push('f');
        for &v in f {
            let _ = write!(s, " {}/{}", v + 1, chart * nv + v as usize + 1);
        }
        s.push('\n');
    }
    let _ = writeln!(
        s,
        "t facevaryinginterpolateboundary 1/0/0 {}",
        rng.next_u64() % 6
    );
    s
}
