//! The pixel-error mode (beyond Settgast et al.): the least depth whose drawn triangles stay
//! within a screen-space error of the limit surface.
//!
//! What the mode knows of each patch is measured once per cage ([`PatchError`]: the chord error
//! of the drawn triangles at every depth, and a cone bounding the patch's limit normals); per
//! frame it is projected conservatively:
//!
//! - **Projection.** A world displacement `δ` at view-space point `p = (X, Y, Z)` moves its image
//!   by at most `f |δ| |p| / Z²` pixels (`f` the focal length in pixels: the largest singular
//!   value of the Jacobian of `(X/Z, Y/Z)` is `|p| / Z²`). Over a patch's bounding sphere
//!   (centre `c`, radius `r`) that is at most `f (|c − eye| + r) / (Z_c − r)²`
//!   ([`screen_scale`]); on the axis this is the familiar `f / Z`, off-axis it grows with the
//!   secant of the angle, which a plain `f / distance` would miss.
//! - **Shading.** The silhouette bound says nothing of the normals the renderer interpolates
//!   across a patch's triangles, and shading follows the normals: a patch drawn at depth 1 can
//!   keep its outline within a pixel and still be shaded as a few flat-ish facets. Each face
//!   therefore also records where, at each depth, the interpolated normal turns further than a
//!   tolerance from the limit normal ([`PatchError::shading`]), and after the silhouette depths
//!   the faces are raised until at most 1 % of the visible pixels (the benchmark's
//!   `shading_deg_p99`) are beyond it, the tolerance spent over the whole image rather than per
//!   patch ([`crate::shading`]). Diffuse intensity `n · l` moves by at most `sin θ` of full
//!   scale when the normal turns by `θ`, whatever the view, so the tolerance is an angle
//!   ([`DepthParams::shading_error_deg`](crate::DepthParams)), not a number of pixels.
//! - **Hidden patches.** A patch is drawn at depth 0 without error only when it is provably
//!   invisible: the mesh is closed (no boundary, no holes, so every ray that meets a back-facing
//!   point first meets a front-facing one) and every normal of the patch faces away from every
//!   eye ray into its bounding sphere ([`PatchError::faces_away`]). The vertex classification of
//!   §3.1 is not enough here: a face whose corner normals all face away can still carry the
//!   silhouette inside it.

use glam::Vec3;
use subdiv_mesh::Camera;

use crate::Depth;
use crate::shading::ShadingError;
use crate::sphere::Sphere;

/// A cone bounding a set of unit normals: every normal `n` satisfies `n · axis >= cos`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalCone {
    /// Unit axis.
    pub axis: Vec3,
    /// Cosine of the half-angle; `-1` (or less) bounds nothing.
    pub cos: f32,
}

impl NormalCone {
    /// The cone that bounds nothing (any normal).
    pub const ANY: NormalCone = NormalCone {
        axis: Vec3::Z,
        cos: -1.0,
    };

    /// A cone around the normalised mean of `normals` containing all of them, widened by
    /// `margin` radians (normals between the samples can lean further than the samples).
    pub fn bounding(normals: impl Iterator<Item = Vec3> + Clone, margin: f32) -> NormalCone {
        let sum: Vec3 = normals.clone().sum();
        let axis = sum.normalize_or_zero();
        if axis == Vec3::ZERO {
            return NormalCone::ANY;
        }
        let min_cos = normals.map(|n| n.dot(axis)).fold(1.0f32, f32::min);
        let half = min_cos.clamp(-1.0, 1.0).acos() + margin;
        if half >= std::f32::consts::PI {
            return NormalCone::ANY;
        }
        NormalCone {
            axis,
            cos: half.cos(),
        }
    }
}

/// What the pixel-error mode knows of one cage face (one patch or one unit of level-1
/// patches), measured once per cage.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchError {
    /// Per depth `0..=max_depth`: the largest distance (world units) between the limit surface
    /// and the triangles drawn for the face at that depth.
    pub deviation: Vec<f32>,
    /// Where the normal interpolated across the triangles drawn at each depth (what the
    /// renderer shades with) turns further than the tolerance from the limit normal.
    pub shading: ShadingError,
    /// A cone containing every limit normal of the face's patch(es).
    pub normals: NormalCone,
    /// The face touches the cage's boundary or a hole: the surface's own edge runs along or
    /// near it and is an outline on screen from any side.
    pub outline: bool,
}

impl PatchError {
    /// `true` when every normal of the patch faces away from every eye ray into `sphere`
    /// (angle between the cone's axis and the ray to the centre, plus the cone's half-angle,
    /// plus the sphere's angular radius, below 90°). Conservative: `false` when unsure.
    pub fn faces_away(&self, camera: &Camera, sphere: &Sphere) -> bool {
        let to_centre = sphere.centre - camera.eye;
        let dist = to_centre.length();
        if dist <= sphere.radius || self.normals.cos <= -1.0 {
            return false;
        }
        let view = (to_centre / dist)
            .dot(self.normals.axis)
            .clamp(-1.0, 1.0)
            .acos();
        let cone = self.normals.cos.clamp(-1.0, 1.0).acos();
        let sphere_angle = (sphere.radius / dist).clamp(0.0, 1.0).asin();
        view + cone + sphere_angle < std::f32::consts::FRAC_PI_2
    }
}

/// The pixel-error data of a cage: one [`PatchError`] per face, and whether the surface is
/// closed (no boundary edges, no holes), which allows hidden patches to stay at depth 0.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PatchErrors {
    /// Per cage face.
    pub faces: Vec<PatchError>,
    /// No boundary edges and no holes.
    pub closed: bool,
    /// The shading tolerance (radians) that [`PatchError::shading`] was measured for.
    pub shading_tolerance: f32,
}

/// Largest number of pixels a world displacement of length 1 inside `sphere` can move on
/// screen (see the module documentation); infinite when the sphere reaches the eye plane.
#[inline]
pub fn screen_scale(camera: &Camera, sphere: &Sphere) -> f32 {
    let z = camera.depth_of(sphere.centre) - sphere.radius;
    let reach = (sphere.centre - camera.eye).length() + sphere.radius;
    let z_min = 1e-6 * reach.max(1e-6);
    if z <= z_min {
        return f32::INFINITY;
    }
    camera.focal_pixels() * reach / (z * z)
}

/// `true` when `sphere` lies wholly outside `camera`'s view: behind the eye, or beyond one of
/// the four planes through the eye and the image's edges. Nothing inside it reaches a pixel, so
/// a face whose sphere (which contains its limit surface, hence every point drawn for it at any
/// depth, and the fans `subdiv-stitch` draws on its side) is outside has no screen error at
/// depth 0.
pub fn outside_view(camera: &Camera, sphere: &Sphere) -> bool {
    // View space: the eye at the origin looking down -Z; `z` is the depth ahead of the eye.
    let c = camera.view_matrix().transform_point3(sphere.centre);
    let (x, y, z) = (c.x, c.y, -c.z);
    let r = sphere.radius;
    if z < -r {
        return true;
    }
    let f = camera.focal_pixels();
    let (hw, hh) = (camera.width as f32 * 0.5, camera.height as f32 * 0.5);
    // Signed distances to the side planes `x f = ±z hw` and `y f = ±z hh`, positive outside.
    let (nx, ny) = ((f * f + hw * hw).sqrt(), (f * f + hh * hh).sqrt());
    (x.abs() * f - z * hw) / nx > r || (y.abs() * f - z * hh) / ny > r
}

/// The least depth whose chord error `e.deviation[l]`, projected by [`screen_scale`], is at most
/// `px` pixels; `max_depth` when none is.
pub fn pixel_error_depth(
    camera: &Camera,
    s: &Sphere,
    e: &PatchError,
    px: f32,
    max_depth: Depth,
) -> Depth {
    let scale = screen_scale(camera, s);
    for (l, &dev) in e.deviation.iter().enumerate().take(max_depth as usize + 1) {
        if dev * scale <= px {
            return l as Depth;
        }
    }
    max_depth
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(eye: Vec3, target: Vec3) -> Camera {
        Camera::new(eye, target, Vec3::Y, 60.0, 800, 600)
    }

    #[test]
    fn screen_scale_bounds_the_true_projection() {
        // Move points of a sphere by small displacements in many directions: the projected
        // motion never exceeds the bound, and the bound is tight on the axis.
        let c = cam(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO);
        let mut seed = 7u32;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        for centre in [
            Vec3::ZERO,
            Vec3::new(3.0, 2.0, 0.0),
            Vec3::new(-4.0, 0.5, 4.0),
        ] {
            let s = Sphere {
                centre,
                radius: 1.0,
            };
            let bound = screen_scale(&c, &s);
            for _ in 0..2000 {
                let p = centre + Vec3::new(rnd(), rnd(), rnd()).clamp_length_max(1.0);
                let d = Vec3::new(rnd(), rnd(), rnd()).normalize_or_zero() * 1e-3;
                let (a, b) = (c.project(p).unwrap(), c.project(p + d).unwrap());
                assert!((a - b).length() <= bound * 1e-3 * 1.001, "{centre}");
            }
        }
        let on_axis = Sphere {
            centre: Vec3::ZERO,
            radius: 0.01,
        };
        let f_over_z = c.focal_pixels() / 10.0;
        assert!((screen_scale(&c, &on_axis) / f_over_z - 1.0).abs() < 0.01);
        let at_eye = Sphere {
            centre: Vec3::new(0.0, 0.0, 10.5),
            radius: 1.0,
        };
        assert!(screen_scale(&c, &at_eye).is_infinite());
    }

    #[test]
    fn outside_view_only_when_no_point_of_the_sphere_projects_into_the_image() {
        let c = cam(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO);
        let mut seed = 11u32;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        let inside = |p: Vec3| {
            c.project(p)
                .is_some_and(|q| q.x >= 0.0 && q.y >= 0.0 && q.x <= 800.0 && q.y <= 600.0)
        };
        let (mut culled, mut kept) = (0, 0);
        for _ in 0..400 {
            let s = Sphere {
                centre: Vec3::new(rnd() * 20.0, rnd() * 15.0, rnd() * 20.0),
                radius: 0.2 + rnd().abs() * 2.0,
            };
            if outside_view(&c, &s) {
                culled += 1;
                // No point of the sphere lands in the image.
                for _ in 0..300 {
                    let d = Vec3::new(rnd(), rnd(), rnd()).clamp_length_max(1.0);
                    assert!(!inside(s.centre + d * s.radius), "{s:?}");
                }
            } else {
                kept += 1;
            }
        }
        assert!(culled > 50 && kept > 50, "{culled} {kept}");
        // Tight: a sphere just beyond the right edge is outside, one reaching into it is not
        // (the side plane is slanted: its distance from a point `dx` beyond the edge at depth
        // 10 is `dx f / sqrt(f² + 400²)`, about 0.79 dx here).
        let edge = |x: f32| Sphere {
            centre: Vec3::new(x, 0.0, 0.0),
            radius: 0.5,
        };
        let half_width = 10.0 * 400.0 / c.focal_pixels();
        assert!(outside_view(&c, &edge(half_width + 0.7)));
        assert!(!outside_view(&c, &edge(half_width + 0.4)));
        // Behind the eye.
        let behind = Sphere {
            centre: Vec3::new(0.0, 0.0, 11.0),
            radius: 0.5,
        };
        assert!(outside_view(&c, &behind));
    }

    #[test]
    fn pixel_error_depth_is_least_sufficient() {
        let s = Sphere {
            centre: Vec3::ZERO,
            radius: 1.0,
        };
        let c = cam(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO);
        let dev = vec![0.5, 0.12, 0.03, 0.008, 0.002, 0.0005];
        let e = PatchError {
            deviation: dev.clone(),
            shading: ShadingError::default(),
            normals: NormalCone::ANY,
            outline: false,
        };
        let scale = screen_scale(&c, &s);
        let d = pixel_error_depth(&c, &s, &e, 1.0, 5);
        assert!(dev[d as usize] * scale <= 1.0);
        assert!(d == 0 || dev[d as usize - 1] * scale > 1.0);
        // Never beyond the cap, even when no depth suffices.
        assert_eq!(pixel_error_depth(&c, &s, &e, 1e-9, 3), 3);
        assert_eq!(pixel_error_depth(&c, &s, &e, 1e9, 5), 0);
    }

    #[test]
    fn faces_away_needs_the_whole_cone_and_sphere_turned_away() {
        let c = cam(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO);
        let s = Sphere {
            centre: Vec3::ZERO,
            radius: 0.5,
        };
        let patch = |axis: Vec3, half_deg: f32| PatchError {
            deviation: vec![0.0],
            shading: ShadingError::default(),
            normals: NormalCone {
                axis,
                cos: half_deg.to_radians().cos(),
            },
            outline: false,
        };
        // Normals pointing away from the eye (along -z) within 30°: hidden.
        assert!(patch(-Vec3::Z, 30.0).faces_away(&c, &s));
        // Facing the eye: visible.
        assert!(!patch(Vec3::Z, 30.0).faces_away(&c, &s));
        // Turned away by 80° but with a 20° cone: some normals may face the eye.
        let axis = Vec3::new(10f32.to_radians().sin(), 0.0, -(10f32.to_radians().cos()));
        assert!(patch(axis, 20.0).faces_away(&c, &s));
        let axis = Vec3::new(80f32.to_radians().sin(), 0.0, -(80f32.to_radians().cos()));
        assert!(!patch(axis, 20.0).faces_away(&c, &s));
        // No bound: never hidden.
        let any = PatchError {
            deviation: vec![0.0],
            shading: ShadingError::default(),
            normals: NormalCone::ANY,
            outline: false,
        };
        assert!(!any.faces_away(&c, &s));
    }

    #[test]
    fn bounding_cones_contain_their_normals() {
        let ns = [
            Vec3::Z,
            Vec3::new(0.3, 0.0, 1.0).normalize(),
            Vec3::new(0.0, -0.4, 1.0).normalize(),
        ];
        let cone = NormalCone::bounding(ns.iter().copied(), 0.0);
        assert!(ns.iter().all(|n| n.dot(cone.axis) >= cone.cos - 1e-6));
        let wider = NormalCone::bounding(ns.iter().copied(), 0.1);
        assert!(wider.cos < cone.cos);
        // Opposite normals: no bound.
        let flat = NormalCone::bounding([Vec3::Z, -Vec3::Z].into_iter(), 0.0);
        assert_eq!(flat.cos, -1.0);
    }
}
