//! Per-frame depth assignment (Settgast et al. 2004, Section 3.1): back/front/silhouette
//! classification of vertices and faces (after Luebke and Erikson 1997), curvature depths for
//! front faces (and for back faces of an open surface, whose back side can be seen), the
//! average of `maxsd` and the curvature depth for silhouette faces, then the projected-size
//! adjustment; or, beyond the paper, the least depth whose drawn triangles stay
//! within a pixel error on screen ([`crate::pixel_error`]).

use glam::Vec3;
use subdiv_mesh::{Camera, Mesh};

use crate::contour::contour_pixels;
use crate::curvature::VertexData;
use crate::pixel_error::{PatchErrors, outside_view, pixel_error_depth};
use crate::shading::raise_for_shading;
use crate::sphere::Sphere;
use crate::{DEFAULT_MAX_DEPTH, Depth};

/// Default [`DepthParams::shading_error_deg`]: 10°, the 99th percentile of the image's normal
/// error that the pixel-error mode aims at. Below about 5° it is out of reach on scenes with
/// many silhouettes whatever the depth (helmet40: uniform depth 5 has 4.7°, its contour pixels
/// are 15 % of the image), and the budget then raises every face it counts to `max_depth`
/// without lowering the percentile: 2° and 4° draw 1.78 M and 1.69 M triangles there for 8.1°
/// and 8.5°, 8° 1.25 M for 8.1°, 10° 1.04 M for 9.1° (raw outputs:
/// docs/bench/quality/quality_helmet_line{_s2,_s4,_s8,}.txt).
/// 10° is the smallest swept tolerance with which the mode meets its targets on both the
/// pawn and helmet40 (8° misses helmet40 by 1.4 points); a normal off by `θ` moves diffuse
/// intensity `n · l` by at most `sin θ` of full scale (17 % at 10°), so lower it for still
/// images of smooth objects (the pawn's top view: 2° draws 131 k triangles for 1.0°).
pub const DEFAULT_SHADING_ERROR_DEG: f32 = 10.0;

/// Default [`DepthParams::cone_aperture_deg`]: 10°. At the curvature depth the face normals
/// around a vertex lie within this angle of its limit normal, and the chord of a sub-patch `rho`
/// pixels in radius whose normals turn by `alpha` deviates by about `rho * alpha / 4` pixels
/// ([`priority`]): 0.17 px at `rho` = 4 px ([`DEFAULT_PROJECTED_SIZE`]). Swept 5°, 10°, 20°
/// (raw outputs: docs/bench/quality/quality_sweep_*.txt): with the 1..4 px band, 5° costs
/// 6-33 % more triangles for at most 0.03° less shading error, 20° saves up to 22 % and has up
/// to a third more shading error (teapot).
pub const DEFAULT_CONE_APERTURE_DEG: f32 = 10.0;

/// Default [`DepthParams::classifier_eps`]: 0.1, a silhouette band of normals within
/// `asin 0.1 = 5.7°` of edge-on (the paper gives no value). Swept 0.1 and 0.17 (`sin 10°`, the
/// cone aperture): under 1 % more triangles for under 0.1° less shading error and the same
/// silhouettes, so the narrower band stays.
pub const DEFAULT_CLASSIFIER_EPS: f32 = 0.1;

/// Default [`DepthParams::projected_size`]: sub-patch radii between 0.9 and 4 pixels.
/// `R_max = 4 px`: with the cone aperture's normal spread the chord of such a sub-patch stays
/// within 0.2 px, and `R_max >= 2 R_min` keeps the band one level wide at least
/// ([`adjust_projected`] lands in it whenever a depth can). `R_min` sets how far small patches
/// (distant objects) are coarsened, and the shading of their pixels pays for it: a sub-patch
/// a pixel or two across still spans the normals of a curved region, and each pixel shows
/// their interpolation. Swept on helmet40 (`bench framerate`, the Fig. 5 orbit at 640×480,
/// maximum depth 4, error of every 10th frame against uniform depth 5; uniform depth 3: 296,960
/// triangles, 12.68° shading p99; uniform depth 4: 1,187,840, 5.34°), triangles / median
/// shading p99: `R_min` 1 px 325 k / 13.99° (worse than uniform depth 3 with more triangles),
/// 0.9 px 383 k / 12.37°, 0.85 px 417 k / 11.70°, 0.75 px 498 k / 10.03°, 0.6 px 666 k / 7.74°,
/// 0.5 px 799 k / 6.51°; silhouettes exact in every case (raw output:
/// docs/bench/paper-mode-helmet40-*.txt). 0.9 px is the largest swept value whose picture
/// beats uniform depth 3's, at a third of uniform depth 4's triangles; at `bench quality`'s
/// helmet40 camera (800×600, maximum depth 4) it draws 48 % of uniform depth 4's triangles for
/// 11.2° against uniform depth 3's 16.2° (maximum depth 5: 52 %, 1 px 44 %; both near the line
/// between the uniform depths, docs/performance.md). On scenes whose patches are large on screen (the pawn, the
/// 3-torus, a helmet, a creased torus, the teapot filling the view) `R_min` below 1 px changes
/// at most a few per cent of the triangles. The paper gives no values.
pub const DEFAULT_PROJECTED_SIZE: (f32, f32) = (0.9, 4.0);

/// The paper's user parameters, plus the pixel-error mode and back-face culling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthParams {
    /// Deepest depth (`maxsd`). Default [`DEFAULT_MAX_DEPTH`].
    pub max_depth: Depth,
    /// `NormalConeAperture` in degrees. Default [`DEFAULT_CONE_APERTURE_DEG`].
    pub cone_aperture_deg: f32,
    /// `VertexClassifier` epsilon on `ln . camray`. Default [`DEFAULT_CLASSIFIER_EPS`].
    pub classifier_eps: f32,
    /// `ProjectedSizeMin/Max`: sub-patch radius bounds in pixels (`None`: no adjustment).
    /// Default [`DEFAULT_PROJECTED_SIZE`].
    pub projected_size: Option<(f32, f32)>,
    /// Screen-space error bound in pixels (replaces curvature and projected size when set).
    pub pixel_error: Option<f32>,
    /// With `pixel_error`: the angle in degrees between the limit normal and the normal
    /// interpolated across the drawn triangles that 99 % of the visible pixels must stay within
    /// ([`crate::shading`]); 180 bounds silhouettes only. Default
    /// [`DEFAULT_SHADING_ERROR_DEG`].
    pub shading_error_deg: f32,
    /// Leave back faces out instead of drawing them at depth 0.
    pub cull_back: bool,
}

impl Default for DepthParams {
    fn default() -> Self {
        DepthParams {
            max_depth: DEFAULT_MAX_DEPTH,
            cone_aperture_deg: DEFAULT_CONE_APERTURE_DEG,
            classifier_eps: DEFAULT_CLASSIFIER_EPS,
            projected_size: Some(DEFAULT_PROJECTED_SIZE),
            pixel_error: None,
            shading_error_deg: DEFAULT_SHADING_ERROR_DEG,
            cull_back: false,
        }
    }
}

/// Orientation of a vertex or face relative to the viewer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// Facing away (`ln . camray > eps`).
    Back,
    /// Facing the viewer (`ln . camray < -eps`).
    Front,
    /// In between.
    Silhouette,
}

/// Classifies a vertex with limit point `lp` and limit normal `ln`.
#[inline]
pub fn classify_vertex(camera: &Camera, lp: Vec3, ln: Vec3, eps: f32) -> Class {
    let d = ln.dot(camera.ray_to(lp));
    if d > eps {
        Class::Back
    } else if d < -eps {
        Class::Front
    } else {
        Class::Silhouette
    }
}

/// Projected radius in pixels of a sphere (infinite when the eye is inside it).
#[inline]
pub fn projected_radius(camera: &Camera, s: &Sphere) -> f32 {
    let d = (s.centre - camera.eye).length();
    if d <= s.radius {
        return f32::INFINITY;
    }
    s.radius * camera.focal_pixels() / (d * d - s.radius * s.radius).sqrt()
}

/// The projected-size adjustment of Section 3.1, for a patch whose bounding sphere projects to
/// radius `r` pixels, so that its sub-patches at depth `l` measure `R 2^-l`:
///
/// * if `R 2^-l > r_max`, the least `s` with `R 2^-(l+s) <= r_max` further levels (at most up
///   to `max_depth`): depth `l + s`;
/// * if `R 2^-l < r_min`, the least `s` with `R 2^-(l-s) >= r_min`, over any number of levels:
///   depth `l - s`, or depth 0 when even the whole patch (`R`) is below `r_min`;
/// * otherwise `l`.
///
/// With `r_max >= 2 r_min` (the band spans at least one level) the result lies in the band
/// whenever some depth in `0..=max_depth` does.
pub fn adjust_projected(l: Depth, r: f32, (r_min, r_max): (f32, f32), max_depth: Depth) -> Depth {
    let size = |l: Depth| r / (1u32 << l) as f32;
    let mut l = l.min(max_depth);
    if size(l) > r_max {
        while l < max_depth && size(l) > r_max {
            l += 1;
        }
    } else {
        while l > 0 && size(l) < r_min {
            l -= 1;
        }
    }
    l
}

/// The frame-rate control priority of a patch (Section 3.1 leaves the choice open): an estimate,
/// up to a constant factor, of the screen-space chord error of its sub-patches at depth `d`.
/// A sub-patch measures `rho = R 2^-d` pixels; the curvature depth `c` is where the normal
/// spread falls to the cone aperture `alpha`, and the spread halves with every level, so at `d`
/// it is `alpha 2^(c-d)`; a chord across an arc of radius `rho` and turning angle `theta`
/// deviates by about `rho theta / 4`. Dropping the common factor `alpha / 4`:
/// `R 2^(c - 2d)`. Raising the patch with the largest value (or lowering the smallest) buys
/// the most (or costs the least) visible error per patch moved.
#[inline]
pub fn priority(r: f32, curvature: Depth, d: Depth) -> f32 {
    r * ((curvature as i32 - 2 * d as i32) as f32).exp2()
}

/// The result of one frame's assignment.
#[derive(Clone, Debug, Default)]
pub struct Assignment {
    /// Depth per cage face.
    pub depth: Vec<Depth>,
    /// `false` for culled faces.
    pub active: Vec<bool>,
    /// Class per cage face.
    pub class: Vec<Class>,
    /// Projected radius `R` of each face's bounding sphere, in pixels.
    pub radius: Vec<f32>,
    /// Curvature depth of each face (the largest of its vertices').
    pub curvature: Vec<Depth>,
}

impl Assignment {
    /// The frame-rate control [`priority`] of every face at its current depth.
    pub fn priorities(&self) -> Vec<f32> {
        (0..self.depth.len())
            .map(|f| priority(self.radius[f], self.curvature[f], self.depth[f]))
            .collect()
    }
}

/// Assigns a depth to every cage face for `camera`. `errors` (chord errors and normal cones per
/// face, [`PatchErrors`]) is needed only in pixel-error mode: there every face gets the least
/// depth within the error bound unless it is provably hidden (see [`crate::pixel_error`]).
pub fn assign(
    mesh: &Mesh,
    vd: &VertexData,
    spheres: &[Sphere],
    errors: Option<&PatchErrors>,
    camera: &Camera,
    p: &DepthParams,
) -> Assignment {
    let vclass: Vec<Class> = (0..mesh.num_vertices())
        .map(|v| classify_vertex(camera, vd.limit[v], vd.normal[v], p.classifier_eps))
        .collect();
    let mut out = Assignment {
        depth: Vec::with_capacity(mesh.num_faces()),
        ..Assignment::default()
    };
    // Section 3.1 draws back faces at depth 0: on a closed surface they are hidden. On an open
    // one (boundary edges or holes: a helmet, a pawn open at the base) the back side shows
    // through the opening, so back faces are assigned like front faces (their curvature depth,
    // then the projected size); they stay classified `Back` (frame-rate control never raises
    // them, `cull_back` still drops them).
    let back_hidden = mesh.is_closed();
    for f in mesh.faces() {
        let vs = mesh.face_vertices(f);
        let cls = if vs.iter().all(|v| vclass[v.idx()] == Class::Back) {
            Class::Back
        } else if vs.iter().all(|v| vclass[v.idx()] == Class::Front) {
            Class::Front
        } else {
            Class::Silhouette
        };
        let curv = vs.iter().map(|v| vd.depth[v.idx()]).max().unwrap_or(0);
        let mut d = match cls {
            Class::Back if back_hidden => 0,
            Class::Back | Class::Front => curv,
            Class::Silhouette => (p.max_depth + curv).div_ceil(2),
        };
        let sphere = &spheres[f.idx()];
        let r = projected_radius(camera, sphere);
        if let (Some(px), Some(errs)) = (p.pixel_error, errors) {
            let e = &errs.faces[f.idx()];
            // Off screen (on any surface) or provably hidden (closed surface): no screen error.
            d = if outside_view(camera, sphere) || (errs.closed && e.faces_away(camera, sphere)) {
                0
            } else {
                pixel_error_depth(camera, sphere, e, px, p.max_depth)
            };
        } else if (cls != Class::Back || !back_hidden)
            && let Some(ps) = p.projected_size
        {
            d = adjust_projected(d, r, ps, p.max_depth);
        }
        out.depth.push(d.min(p.max_depth));
        out.active.push(!(p.cull_back && cls == Class::Back));
        out.class.push(cls);
        out.radius.push(r);
        out.curvature.push(curv);
    }
    if let (Some(_), Some(errs)) = (p.pixel_error, errors) {
        // The contour runs through the silhouette faces (crate::contour).
        let contour: Vec<f32> = (out.class.iter().zip(&out.radius))
            .map(|(&c, &r)| {
                if c == Class::Silhouette {
                    contour_pixels(r)
                } else {
                    0.0
                }
            })
            .collect();
        raise_for_shading(
            camera,
            errs,
            &out.active,
            &contour,
            &mut out.depth,
            p.max_depth,
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(eye: Vec3) -> Camera {
        Camera::new(eye, Vec3::ZERO, Vec3::Y, 60.0, 800, 600)
    }

    #[test]
    fn classification() {
        let c = cam(Vec3::new(0.0, 0.0, 10.0));
        // A point at the origin facing the camera is front, facing away back, sideways silhouette.
        assert_eq!(classify_vertex(&c, Vec3::ZERO, Vec3::Z, 0.1), Class::Front);
        assert_eq!(classify_vertex(&c, Vec3::ZERO, -Vec3::Z, 0.1), Class::Back);
        assert_eq!(
            classify_vertex(&c, Vec3::ZERO, Vec3::X, 0.1),
            Class::Silhouette
        );
        // Slightly tilted: within epsilon is silhouette, beyond it front.
        let tilt = Vec3::new(1.0, 0.0, 0.05).normalize();
        assert_eq!(
            classify_vertex(&c, Vec3::ZERO, tilt, 0.1),
            Class::Silhouette
        );
        assert_eq!(classify_vertex(&c, Vec3::ZERO, tilt, 0.01), Class::Front);
    }

    #[test]
    fn projected_size_moves_with_distance() {
        let s = Sphere {
            centre: Vec3::ZERO,
            radius: 1.0,
        };
        let near = projected_radius(&cam(Vec3::new(0.0, 0.0, 5.0)), &s);
        let far = projected_radius(&cam(Vec3::new(0.0, 0.0, 50.0)), &s);
        assert!(near > 5.0 * far);
        let dn = adjust_projected(2, near, (2.0, 8.0), 6);
        let df = adjust_projected(2, far, (2.0, 8.0), 6);
        assert!(
            dn > df,
            "moving the camera away must lower the depth: {dn} vs {df}"
        );
        // Within bounds: unchanged.
        assert_eq!(adjust_projected(3, 40.0, (2.0, 8.0), 6), 3);
        // Never beyond max depth.
        assert_eq!(adjust_projected(0, 1e6, (2.0, 8.0), 4), 4);
    }

    #[test]
    fn projected_size_coarsens_any_number_of_levels() {
        // R = 20 px: depth 5 gives 0.625 px sub-patches; the least s with 20 2^-(5-s) >= 2
        // is s = 2 (depth 3: 2.5 px); depth 4 (1.25 px) would still be below r_min.
        assert_eq!(adjust_projected(5, 20.0, (2.0, 8.0), 5), 3);
        // R = 4 px: three levels up, to depth 1 (2 px).
        assert_eq!(adjust_projected(4, 4.0, (2.0, 8.0), 5), 1);
        // A whole patch below r_min (a few pixels for the whole model): depth 0.
        assert_eq!(adjust_projected(5, 1.5, (2.0, 8.0), 5), 0);
        assert_eq!(adjust_projected(5, 0.0, (2.0, 8.0), 5), 0);
        // Deepening: the least s with R 2^-(l+s) <= r_max, several levels at once.
        assert_eq!(adjust_projected(0, 100.0, (2.0, 8.0), 6), 4);
        // Within the band, any depth is left alone.
        for l in 0..=5u8 {
            let r = 5.0 * (1u32 << l) as f32;
            assert_eq!(adjust_projected(l, r, (2.0, 8.0), 5), l);
        }
    }

    #[test]
    fn projected_size_result_is_in_band_when_possible() {
        // r_max = 2 r_min + margin: for any R and start depth the result is in the band
        // whenever some depth of 0..=6 is.
        let band = (2.0, 8.0);
        for i in 0..400 {
            let r = 0.1 * 1.03f32.powi(i);
            for l in 0..=6u8 {
                let d = adjust_projected(l, r, band, 6);
                let size = r / (1u32 << d) as f32;
                let possible = (0..=6).any(|k| {
                    let s = r / (1u32 << k) as f32;
                    s >= band.0 && s <= band.1
                });
                if possible {
                    assert!(size >= band.0 && size <= band.1, "R {r} from {l}: {d}");
                } else {
                    assert!(d == 0 || d == 6, "R {r} from {l}: {d}");
                }
            }
        }
    }

    /// The cube `[-1, 1]^3` (8 vertices, 6 quads, its `y = 1` face last), optionally without
    /// that top face (open).
    fn cube(open: bool) -> Mesh {
        let mut c = subdiv_test_support::cube().map_positions(|p| p.map(|x| 2.0 * x - 1.0));
        let top = c.faces.remove(3);
        if !open {
            c.faces.push(top);
        }
        Mesh::from_soup(&subdiv_mesh::parse_obj(&c.obj()).unwrap()).unwrap()
    }

    #[test]
    fn back_faces_of_an_open_surface_are_assigned_like_front_faces() {
        // Seen from far above (+Y) the bottom face is a back face. The closed cube hides it:
        // depth 0. The open cube (no top face) shows its floor through the opening: its back
        // faces get their curvature depth like front faces.
        let p = DepthParams {
            projected_size: None,
            ..DepthParams::default()
        };
        let camera = cam(Vec3::new(0.3, 12.0, 0.2));
        for open in [false, true] {
            let mesh = cube(open);
            assert_eq!(mesh.is_closed(), !open);
            let vd = VertexData::compute(
                &mesh,
                subdiv_rules::Scheme::CatmullClark,
                p.cone_aperture_deg,
                p.max_depth,
            );
            let spheres = crate::sphere::face_spheres(&mesh, subdiv_rules::Scheme::CatmullClark);
            let a = assign(&mesh, &vd, &spheres, None, &camera, &p);
            let back: Vec<usize> = (0..a.depth.len())
                .filter(|&f| a.class[f] == Class::Back)
                .collect();
            assert!(!back.is_empty());
            for f in back {
                let want = if open { a.curvature[f] } else { 0 };
                assert_eq!(a.depth[f], want, "open {open}, face {f}");
                assert!(a.curvature[f] > 0, "a cube's corners are curved");
            }
        }
    }

    #[test]
    fn priority_prefers_large_curved_coarse_patches() {
        assert!(priority(100.0, 3, 2) > priority(50.0, 3, 2));
        assert!(priority(100.0, 4, 2) > priority(100.0, 3, 2));
        assert!(priority(100.0, 3, 1) > priority(100.0, 3, 2));
        // One level deeper quarters the estimate (size and normal spread both halve).
        assert_eq!(priority(64.0, 2, 3) * 4.0, priority(64.0, 2, 2));
    }
}
