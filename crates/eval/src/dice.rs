//! Dicing by pixels: each cage edge's rate from the length of its limit curve on screen
//! (Blender Cycles' definition: the edge's projected length in pixels over the dicing rate,
//! rounded up), with the parts of the curve outside the view frustum (or behind the camera)
//! counted at the dicing rate times an off-screen scale.
//!
//! The curve is sampled at [`CURVE_SEGMENTS`] steps of its parameter (evaluated from the face
//! that owns the edge's points in the tessellation), each step projected with the camera.
//! Behind the camera a step counts its length as seen at its distance. Back faces are diced as
//! front faces are (no culling: the surface is complete from any side).

use glam::{DVec3, Vec2};
use subdiv_mesh::{Camera, FaceId};

use crate::tess::MAX_RATE;
use crate::{
    Derivatives, Domain, EdgeRates, EvalError, Evaluator, Query, Sample, Tessellation,
    tessellate_rates,
};

/// Steps of an edge's limit curve measured on screen.
pub const CURVE_SEGMENTS: u32 = 8;

/// Cycles' default off-screen dicing scale.
pub const DEFAULT_OFFSCREEN_DICING_SCALE: f32 = 4.0;

/// How finely to dice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dicing {
    /// Target length of a tessellation edge on screen, in pixels (Cycles' "dicing rate").
    pub rate_px: f32,
    /// Off screen the dicing rate is this many times coarser.
    pub offscreen_scale: f32,
    /// The largest rate of an edge (at most [`MAX_RATE`]).
    pub max_rate: u32,
}

impl Dicing {
    /// Dicing at `rate_px` pixels, Cycles' default off-screen scale, rates up to 256.
    pub fn new(rate_px: f32) -> Dicing {
        Dicing {
            rate_px,
            offscreen_scale: DEFAULT_OFFSCREEN_DICING_SCALE,
            max_rate: 256,
        }
    }
}

/// The on-screen and off-screen pixel length of a curve through `points`.
fn screen_length(camera: &Camera, points: &[DVec3]) -> (f64, f64) {
    let (w, h) = (camera.width as f32, camera.height as f32);
    let on_screen =
        |p: Option<Vec2>| p.is_some_and(|p| p.x >= 0.0 && p.y >= 0.0 && p.x <= w && p.y <= h);
    let focal = f64::from(camera.focal_pixels());
    let (mut on, mut off) = (0.0, 0.0);
    for pair in points.windows(2) {
        let (a, b) = (pair[0].as_vec3(), pair[1].as_vec3());
        let (pa, pb) = (camera.project(a), camera.project(b));
        let px = match (pa, pb) {
            (Some(pa), Some(pb)) => f64::from(pa.distance(pb)),
            _ => {
                // Behind the camera: the length as seen at its distance.
                let d =
                    f64::from((a - camera.eye).length().min((b - camera.eye).length())).max(1e-12);
                (pair[1] - pair[0]).length() * focal / d
            }
        };
        if on_screen(pa) || on_screen(pb) {
            on += px;
        } else {
            off += px;
        }
    }
    (on, off)
}

/// The rate of every cage edge for `camera` ([module docs](self)).
pub fn dicing_rates(
    eval: &Evaluator<'_>,
    camera: &Camera,
    d: &Dicing,
) -> Result<EdgeRates, EvalError> {
    let mesh = eval.mesh();
    let k = CURVE_SEGMENTS as usize;
    // Each edge's curve, from the first face (in face order) that is not a hole, as the
    // tessellation's owners take it.
    let mut owner: Vec<Option<(FaceId, usize, bool)>> = vec![None; mesh.num_edges()];
    for f in mesh.faces().filter(|&f| !mesh.is_hole(f)) {
        let mut h = mesh.face_halfedge(f);
        for i in 0..mesh.face_size(f) {
            owner[h.edge().idx()].get_or_insert((f, i, h == h.edge().halfedge(0)));
            h = mesh.next(h);
        }
    }
    let mut queries = Vec::with_capacity(mesh.num_edges() * (k + 1));
    for o in owner.iter().flatten() {
        let (f, i, forward) = *o;
        let domain = Domain::of(eval.scheme(), mesh.face_size(f));
        for m in 0..=k {
            let t = m as f64 / k as f64;
            let [u, v] = domain.edge_point(i, if forward { t } else { 1.0 - t });
            queries.push(Query::new(f.0, u, v));
        }
    }
    let mut samples = vec![Sample::default(); queries.len()];
    eval.evaluate_many(&queries, Derivatives::First, &mut samples)?;
    let mut curves = samples.chunks(k + 1);
    let rate_px = f64::from(d.rate_px.max(1e-3));
    let scale = f64::from(d.offscreen_scale.max(1.0));
    let max = d.max_rate.clamp(1, MAX_RATE);
    let rates = owner
        .iter()
        .map(|o| {
            let Some(curve) = o.and_then(|_| curves.next()) else {
                return 1;
            };
            let points: Vec<DVec3> = curve.iter().map(|s| s.position).collect();
            let (on, off) = screen_length(camera, &points);
            let r = (on / rate_px + off / (rate_px * scale)).ceil();
            if r.is_finite() {
                (r as u32).clamp(1, max)
            } else {
                max
            }
        })
        .collect();
    Ok(EdgeRates::from_rates(rates))
}

/// The tessellation of `eval`'s cage diced for `camera`: [`dicing_rates`], then
/// [`tessellate_rates`].
pub fn dice(eval: &Evaluator<'_>, camera: &Camera, d: &Dicing) -> Result<Tessellation, EvalError> {
    tessellate_rates(eval, &dicing_rates(eval, camera, d)?)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use subdiv_mesh::{Camera, Mesh, PolygonSoup};
    use subdiv_rules::Scheme;

    use super::*;

    /// A flat 8 x 8 grid of unit cells seen from 10 above with a 90° field of view on 200 x 200
    /// pixels: a unit at distance 10 covers 10 pixels, and an inner edge's limit curve is the
    /// edge itself (a flat regular grid's limit is the plane, its parameter uniform).
    #[test]
    fn rates_are_screen_length_over_the_dicing_rate() {
        let g = subdiv_test_support::grid(8, 8, false, |i, j| {
            Vec3::new(i as f32 - 4.0, j as f32 - 4.0, 0.0)
        });
        let mesh = Mesh::from_soup(&PolygonSoup::from_faces(g.positions, &g.faces)).unwrap();
        let eval = Evaluator::new(&mesh, Scheme::CatmullClark).unwrap();
        let camera = |eye: Vec3| Camera::new(eye, eye - Vec3::Z * 10.0, Vec3::Y, 90.0, 200, 200);
        // The inner edge from (0, 0) to (1, 0) (grid vertices 40 and 41).
        let inner = mesh
            .edges()
            .find(|&e| {
                let [a, b] = mesh.edge_vertices(e);
                (a.0.min(b.0), a.0.max(b.0)) == (40, 41)
            })
            .unwrap();
        let at = |eye: Vec3, d: &Dicing| dicing_rates(&eval, &camera(eye), d).unwrap().get(inner);
        let d = Dicing::new(3.0);
        assert_eq!(at(Vec3::new(0.0, 0.0, 10.0), &d), 4); // ceil(10 / 3)
        assert_eq!(at(Vec3::new(0.0, 0.0, 10.0), &Dicing::new(0.5)), 20);
        // Looking away to the side: the edge is off screen, at 4 x 3 px.
        assert_eq!(at(Vec3::new(40.0, 0.0, 10.0), &d), 1); // ceil(10 / 12)
        let fine = Dicing {
            offscreen_scale: 1.0,
            ..Dicing::new(1.0)
        };
        assert_eq!(at(Vec3::new(40.0, 0.0, 10.0), &fine), 10);
        let capped = Dicing {
            max_rate: 7,
            ..Dicing::new(0.5)
        };
        assert_eq!(at(Vec3::new(0.0, 0.0, 10.0), &capped), 7);
    }
}
