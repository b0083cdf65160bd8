//! Per-frame depth assignment (Settgast et al. 2004, Section 3.1): back/front/silhouette
//! classification of vertices and faces (after Luebke and Erikson 1997), curvature depths for
//! front faces, the average of `maxsd` and the curvature depth for silhouette faces, then the
//! projected-size adjustment; or, beyond the paper, the least depth whose chord quads stay within
//! a pixel error on screen.

use glam::Vec3;
use subdiv_mesh::{Camera, Mesh};

use crate::curvature::VertexData;

/// The paper's user parameters, plus the pixel-error mode and back-face culling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthParams {
    /// Deepest depth (`maxsd`).
    pub max_depth: u8,
    /// `NormalConeAperture` in degrees.
    pub cone_aperture_deg: f32,
    /// `VertexClassifier` epsilon on `ln . camray`.
    pub classifier_eps: f32,
    /// `ProjectedSizeMin/Max`: sub-patch radius bounds in pixels (`None`: no adjustment).
    pub projected_size: Option<(f32, f32)>,
    /// Screen-space error bound in pixels (replaces curvature and projected size when set).
    pub pixel_error: Option<f32>,
    /// Leave back faces out instead of drawing them at depth 0.
    pub cull_back: bool,
}

impl Default for DepthParams {
    fn default() -> Self {
        DepthParams {
            max_depth: 5,
            cone_aperture_deg: 10.0,
            classifier_eps: 0.1,
            projected_size: Some((2.0, 8.0)),
            pixel_error: None,
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

/// A bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub centre: Vec3,
    /// Radius.
    pub radius: f32,
}

/// A bounding sphere for each cage face's limit patch: centred at the average of its corners'
/// limit points, containing its control points (the limit patch lies in the convex hull of its
/// 1-neighbourhood; the face's own vertices and corner limits are a close, cheap stand-in).
pub fn face_spheres(mesh: &Mesh, vd: &VertexData) -> Vec<Sphere> {
    mesh.faces()
        .map(|f| {
            let vs = mesh.face_vertices(f);
            let centre = vs.iter().map(|v| vd.limit[v.idx()]).sum::<Vec3>() / vs.len() as f32;
            let mut r = 0.0f32;
            for v in vs {
                r = r
                    .max((vd.limit[v.idx()] - centre).length())
                    .max((mesh.position(*v) - centre).length());
            }
            Sphere { centre, radius: r }
        })
        .collect()
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

/// The projected-size adjustment: from depth `l`, deepen while `R 2^-l > r_max`, or go up while
/// `R 2^-l < r_min` (keeping `R 2^-l >= r_min`).
pub fn adjust_projected(l: u8, r: f32, (r_min, r_max): (f32, f32), max_depth: u8) -> u8 {
    let size = |l: u8| r / (1u32 << l) as f32;
    let mut l = l.min(max_depth);
    if size(l) > r_max {
        while l < max_depth && size(l) > r_max {
            l += 1;
        }
    } else if size(l) < r_min {
        while l > 0 && size(l - 1) >= r_min && size(l) < r_min {
            l -= 1;
        }
    }
    l
}

/// The result of one frame's assignment.
#[derive(Clone, Debug, Default)]
pub struct Assignment {
    /// Depth per cage face.
    pub depth: Vec<u8>,
    /// `false` for culled faces.
    pub active: Vec<bool>,
    /// Class per cage face.
    pub class: Vec<Class>,
}

/// Assigns a depth to every cage face for `camera`. `deviation[f][l]` (world units) is the chord
/// error of face `f` at depth `l`, needed only in pixel-error mode.
pub fn assign(
    mesh: &Mesh,
    vd: &VertexData,
    spheres: &[Sphere],
    deviation: Option<&[Vec<f32>]>,
    camera: &Camera,
    p: &DepthParams,
) -> Assignment {
    let vclass: Vec<Class> = (0..mesh.num_vertices())
        .map(|v| classify_vertex(camera, vd.limit[v], vd.normal[v], p.classifier_eps))
        .collect();
    let mut out = Assignment {
        depth: Vec::with_capacity(mesh.num_faces()),
        active: Vec::new(),
        class: Vec::new(),
    };
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
            Class::Back => 0,
            Class::Front => curv,
            Class::Silhouette => (p.max_depth + curv).div_ceil(2),
        };
        if cls != Class::Back {
            if let (Some(px), Some(dev)) = (p.pixel_error, deviation) {
                d = pixel_error_depth(camera, &spheres[f.idx()], &dev[f.idx()], px, p.max_depth);
            } else if let Some(ps) = p.projected_size {
                d = adjust_projected(
                    d,
                    projected_radius(camera, &spheres[f.idx()]),
                    ps,
                    p.max_depth,
                );
            }
        }
        out.depth.push(d.min(p.max_depth));
        out.active.push(!(p.cull_back && cls == Class::Back));
        out.class.push(cls);
    }
    out
}

/// The least depth whose chord error, projected at the sphere's nearest point, is at most `px`.
pub fn pixel_error_depth(camera: &Camera, s: &Sphere, dev: &[f32], px: f32, max_depth: u8) -> u8 {
    let d = ((s.centre - camera.eye).length() - s.radius).max(1e-6 * s.radius.max(1e-6));
    let scale = camera.focal_pixels() / d;
    for (l, &e) in dev.iter().enumerate().take(max_depth as usize + 1) {
        if e * scale <= px {
            return l as u8;
        }
    }
    max_depth
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
    fn pixel_error_depth_is_least_sufficient() {
        let s = Sphere {
            centre: Vec3::ZERO,
            radius: 1.0,
        };
        let c = cam(Vec3::new(0.0, 0.0, 10.0));
        let dev = vec![0.5, 0.12, 0.03, 0.008, 0.002, 0.0005];
        let scale = c.focal_pixels() / 9.0;
        let d = pixel_error_depth(&c, &s, &dev, 1.0, 5);
        assert!(dev[d as usize] * scale <= 1.0);
        assert!(d == 0 || dev[d as usize - 1] * scale > 1.0);
    }
}
