//! Dicing by pixels: each cage edge's rate from the length of its limit curve on screen
//! (Blender Cycles' definition: the edge's projected length in pixels over the dicing rate,
//! rounded up), with the parts of the curve outside the view frustum (or behind the camera)
//! counted at the dicing rate times an off-screen scale; and, beyond Cycles, at least the rate
//! that keeps the curve within a share of the dicing rate of its steps' chords on screen
//! ([`Dicing::flatness`]): at a silhouette the length rule leaves the curves seen end-on in too
//! few steps.
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

/// The default flatness: an edge's steps deviate from their chords on screen by at most this
/// share of the dicing rate ([`Dicing::flatness`]).
pub const DEFAULT_DICING_FLATNESS: f32 = 1.0 / 32.0;

/// How finely to dice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dicing {
    /// Target length of a tessellation edge on screen, in pixels (Cycles' "dicing rate").
    pub rate_px: f32,
    /// Off screen the dicing rate is this many times coarser.
    pub offscreen_scale: f32,
    /// The largest rate of an edge (at most [`MAX_RATE`]).
    pub max_rate: u32,
    /// Beyond Cycles' rule: an edge's steps are also made short enough that its limit curve
    /// strays from their chords on screen by at most `flatness × rate_px` pixels (estimated as
    /// the curve's distance from its whole chord over the square of the rate; a curve wholly
    /// off screen at `offscreen_scale` times that). Length alone leaves a curve seen end-on at
    /// a silhouette, which is short on screen, in few steps that cut the outline. 0: the length
    /// rule alone.
    pub flatness: f32,
}

impl Dicing {
    /// Dicing at `rate_px` pixels, Cycles' default off-screen scale, rates up to 256, the
    /// default flatness.
    pub fn new(rate_px: f32) -> Dicing {
        Dicing {
            rate_px,
            offscreen_scale: DEFAULT_OFFSCREEN_DICING_SCALE,
            max_rate: 256,
            flatness: DEFAULT_DICING_FLATNESS,
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

/// The largest distance on screen of the curve through `points` from its chord, the segment
/// between its ends (0 where part of it is behind the camera). A curve seen end-on, across a
/// silhouette, runs out to the outline and back: its chord is short and its bulge is the
/// distance to the outline.
fn screen_bulge(camera: &Camera, points: &[DVec3]) -> f64 {
    let proj: Option<Vec<Vec2>> = points.iter().map(|p| camera.project(p.as_vec3())).collect();
    let Some(proj) = proj.filter(|p| p.len() >= 2) else {
        return 0.0;
    };
    let (a, b) = (proj[0], proj[proj.len() - 1]);
    let ab = b - a;
    let len2 = ab.length_squared();
    proj.iter()
        .map(|&p| {
            let t = if len2 > 0.0 {
                ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            f64::from(p.distance(a + ab * t))
        })
        .fold(0.0, f64::max)
}

/// The rate of a curve `on` pixels long on screen and `off` pixels off it, straying `bulge`
/// pixels from its chord: the larger of Cycles' rule and the flatness rule (halving a curve's
/// steps quarters its deviation from their chords), a curve wholly off screen held to the
/// off-screen rate by both.
fn curve_rate(on: f64, off: f64, bulge: f64, d: &Dicing) -> u32 {
    let rate_px = f64::from(d.rate_px.max(1e-3));
    let scale = f64::from(d.offscreen_scale.max(1.0));
    let max = d.max_rate.clamp(1, MAX_RATE);
    let flat = if d.flatness > 0.0 {
        let tolerance = rate_px * f64::from(d.flatness) * if on > 0.0 { 1.0 } else { scale };
        (bulge / tolerance).sqrt()
    } else {
        0.0
    };
    let r = (on / rate_px + off / (rate_px * scale)).max(flat).ceil();
    if r.is_finite() {
        (r as u32).clamp(1, max)
    } else {
        max
    }
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
    let rates = owner
        .iter()
        .map(|o| {
            let Some(curve) = o.and_then(|_| curves.next()) else {
                return 1;
            };
            let points: Vec<DVec3> = curve.iter().map(|s| s.position).collect();
            let (on, off) = screen_length(camera, &points);
            curve_rate(on, off, screen_bulge(camera, &points), d)
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

    /// Where a curve bends on screen, in the worst place: across a silhouette, seen end-on. A
    /// half-cylinder (radius 1, its axis along y, 12 cells around) seen from the side: the
    /// edges around it near the contour are short on screen. Measured on the limit curves
    /// themselves (65 points each; the curves wholly on screen), the diced steps stray from
    /// them by at most about the flatness times the rate; with the length rule alone they stray
    /// more than four times as far (here 0.051 px against 0.61 px).
    #[test]
    fn steps_across_a_silhouette_stay_near_the_curve() {
        let g = subdiv_test_support::grid(12, 4, false, |i, j| {
            let a = std::f32::consts::PI * i as f32 / 12.0;
            Vec3::new(a.cos(), j as f32 - 2.0, a.sin())
        });
        let mesh = Mesh::from_soup(&PolygonSoup::from_faces(g.positions, &g.faces)).unwrap();
        let eval = Evaluator::new(&mesh, Scheme::CatmullClark).unwrap();
        let camera = Camera::new(
            Vec3::new(6.0, 0.3, 0.2),
            Vec3::new(0.0, 0.0, 0.6),
            Vec3::Y,
            50.0,
            400,
            400,
        );
        // The largest distance on screen from the limit curve of each edge around the
        // cylinder (face k's first edge, at its rate) to the chords of its steps.
        let worst = |d: &Dicing| -> f64 {
            let rates = dicing_rates(&eval, &camera, d).unwrap();
            let mut worst = 0.0f64;
            for f in mesh.faces() {
                let h = mesh.face_halfedge(f);
                let r = rates.get(h.edge());
                let at = |t: f64| {
                    let [u, v] = Domain::Quad.edge_point(0, t);
                    let p = eval
                        .evaluate(Query::new(f.0, u, v), Derivatives::First)
                        .unwrap();
                    camera.project(p.position.as_vec3()).unwrap()
                };
                // Curves on screen only (those off screen are held to the off-screen rate).
                let inside = |p: Vec2| p.x >= 0.0 && p.y >= 0.0 && p.x <= 400.0 && p.y <= 400.0;
                if !(0..=64).all(|k| inside(at(f64::from(k) / 64.0))) {
                    continue;
                }
                let steps: Vec<Vec2> = (0..=r).map(|m| at(f64::from(m) / f64::from(r))).collect();
                for k in 0..=64 {
                    let t = f64::from(k) / 64.0;
                    let m = ((t * f64::from(r)) as usize).min(r as usize - 1);
                    let (a, b) = (steps[m], steps[m + 1]);
                    let p = at(t);
                    let ab = b - a;
                    let s = if ab.length_squared() > 0.0 {
                        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    worst = worst.max(f64::from(p.distance(a + ab * s)));
                }
            }
            worst
        };
        let d = Dicing::new(2.0);
        let flat = worst(&d);
        let length_only = worst(&Dicing { flatness: 0.0, ..d });
        let bound = f64::from(d.flatness * d.rate_px);
        assert!(flat <= 1.5 * bound, "{flat} px against {bound} px");
        assert!(length_only > 4.0 * bound, "{length_only} px");
    }

    /// A curve's rate: Cycles' rule or the flatness rule, whichever asks for more, each held
    /// to the off-screen rate where the curve lies wholly off screen.
    #[test]
    fn curve_rates_take_the_larger_rule_off_screen_coarser() {
        let d = Dicing::new(2.0); // flatness 1/32: a tolerance of 1/16 px on screen
        assert_eq!(curve_rate(10.0, 0.0, 0.0, &d), 5); // 10 px / 2
        assert_eq!(curve_rate(2.0, 0.0, 1.0, &d), 4); // sqrt(1 / (1/16))
        assert_eq!(curve_rate(0.0, 40.0, 0.0, &d), 5); // 40 px / (2 x 4)
        assert_eq!(curve_rate(0.0, 2.0, 1.0, &d), 2); // sqrt(1 / (4/16))
        let length_only = Dicing { flatness: 0.0, ..d };
        assert_eq!(curve_rate(2.0, 0.0, 1.0, &length_only), 1);
        assert_eq!(curve_rate(f64::INFINITY, 0.0, 0.0, &d), d.max_rate);
    }
}
