//! The evaluation API: one point ([`Evaluator::evaluate`]), one face's points
//! ([`Evaluator::surface`]) and any number of points in parallel
//! ([`Evaluator::evaluate_many`]), positions and UVs.

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use subdiv_mesh::{FaceId, Mesh};
use subdiv_rules::{RulesError, Scheme, check_coordinates, check_doubled_triangles};

use crate::EvalError;
use crate::domain::Domain;
use crate::plan::regular_plans;
use crate::surface::FaceSurface;
use crate::uv::{Uvs, linear_uv, uvs};

/// A parameter point: a cage face (0-based, in file order) and `(u, v)` in its [`Domain`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Query {
    /// The cage face.
    pub face: u32,
    /// First parameter.
    pub u: f64,
    /// Second parameter.
    pub v: f64,
}

impl Query {
    /// The point `(u, v)` of `face`.
    pub fn new(face: u32, u: f64, v: f64) -> Query {
        Query { face, u, v }
    }
}

/// Which derivatives to compute.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Derivatives {
    /// Position and first derivatives (the second ones are left zero).
    #[default]
    First,
    /// Also the second derivatives.
    Second,
}

/// The limit surface at a parameter point: position and derivatives with respect to the
/// face's `(u, v)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    /// Position.
    pub position: DVec3,
    /// `dP/du`.
    pub du: DVec3,
    /// `dP/dv`.
    pub dv: DVec3,
    /// `d2P/du2` (zero unless asked for).
    pub duu: DVec3,
    /// `d2P/dudv` (zero unless asked for).
    pub duv: DVec3,
    /// `d2P/dv2` (zero unless asked for).
    pub dvv: DVec3,
}

impl Sample {
    /// The unit normal `du x dv` (zero where the derivatives are parallel).
    pub fn normal(&self) -> DVec3 {
        self.du.cross(self.dv).normalize_or_zero()
    }
}

/// The face-varying value (UV) at a parameter point and its first derivatives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UvSample {
    /// The value.
    pub uv: DVec2,
    /// `d/du`.
    pub du: DVec2,
    /// `d/dv`.
    pub dv: DVec2,
}

/// Exact evaluation of a cage's limit surface ([crate docs](crate)).
#[derive(Clone, Debug)]
pub struct Evaluator<'m> {
    mesh: &'m Mesh,
    scheme: Scheme,
    uv: Option<Uvs>,
    /// The control points of each fully regular face ([`crate::plan`]), of the cage and of the
    /// UV cage.
    plans: Vec<Option<[u32; 16]>>,
    uv_plans: Vec<Option<[u32; 16]>>,
}

impl<'m> Evaluator<'m> {
    /// An evaluator of `mesh` under `scheme`. Refuses what no refinement path takes: a Loop
    /// cage with a face that is not a triangle or with two triangles on the same three vertices,
    /// coordinates beyond `subdiv_rules::MAX_COORDINATE`. Builds the UV cage when the mesh has
    /// UVs.
    pub fn new(mesh: &'m Mesh, scheme: Scheme) -> Result<Evaluator<'m>, EvalError> {
        check_coordinates(mesh)?;
        if scheme == Scheme::Loop {
            mesh.check_triangles().map_err(RulesError::from)?;
            check_doubled_triangles(mesh)?;
        }
        // Bilinear: face-varying values are linear whatever the option, and no face is a
        // B-spline patch.
        let bilinear = scheme == Scheme::Bilinear;
        let uv = match bilinear {
            true => mesh.uv().map(|_| Uvs::Linear),
            false => uvs(mesh)?,
        };
        let plans = match bilinear {
            true => vec![None; mesh.num_faces()],
            false => regular_plans(mesh, scheme),
        };
        let uv_plans = match &uv {
            Some(Uvs::Cage(m)) => regular_plans(m, scheme),
            _ => Vec::new(),
        };
        Ok(Evaluator {
            mesh,
            scheme,
            uv,
            plans,
            uv_plans,
        })
    }

    /// The cage.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// Whether the cage has UVs ([`Evaluator::evaluate_uv`]).
    pub fn has_uvs(&self) -> bool {
        self.uv.is_some()
    }

    /// The parameter domain of `face`: an error for a face out of range or a hole.
    pub fn domain(&self, face: u32) -> Result<Domain, EvalError> {
        let faces = self.mesh.num_faces() as u32;
        if face >= faces {
            return Err(EvalError::FaceOutOfRange { face, faces });
        }
        if self.mesh.is_hole(FaceId(face)) {
            return Err(EvalError::Hole { face });
        }
        Ok(Domain::of(self.scheme, self.mesh.face_size(FaceId(face))))
    }

    /// Checks a query: its sub-face and normalised coordinates ([`Domain::locate`]).
    pub fn locate(&self, q: Query) -> Result<(usize, f64, f64), EvalError> {
        let domain = self.domain(q.face)?;
        domain
            .locate(q.u, q.v)
            .ok_or_else(|| EvalError::OutsideDomain {
                face: q.face,
                u: q.u,
                v: q.v,
                domain: domain.describe(),
            })
    }

    /// The surface of one face, for evaluating many of its points
    /// ([`FaceSurface::evaluate`]).
    pub fn surface(&self, face: u32) -> Result<FaceSurface, EvalError> {
        let mut s = FaceSurface::new();
        self.load_surface(face, &mut s)?;
        Ok(s)
    }

    /// [`Evaluator::surface`] into an existing surface, reusing its buffers.
    pub fn load_surface(&self, face: u32, surface: &mut FaceSurface) -> Result<(), EvalError> {
        self.domain(face)?;
        let plan = self.plans[face as usize].as_ref();
        surface.load(self.mesh, self.scheme, FaceId(face), plan);
        Ok(())
    }

    /// The limit surface at one point.
    pub fn evaluate(&self, q: Query, d: Derivatives) -> Result<Sample, EvalError> {
        let (sub, s, t) = self.locate(q)?;
        let mut surface = FaceSurface::new();
        let plan = self.plans[q.face as usize].as_ref();
        surface.load(self.mesh, self.scheme, FaceId(q.face), plan);
        Ok(surface.eval_located(sub, s, t, d))
    }

    /// The UV at one point (`None` when the cage has no UVs).
    pub fn evaluate_uv(&self, q: Query) -> Result<Option<UvSample>, EvalError> {
        let (sub, s, t) = self.locate(q)?;
        Ok(match &self.uv {
            None => None,
            Some(Uvs::Linear) => Some(self.linear(q.face, sub, s, t)),
            Some(Uvs::Cage(uv)) => {
                let mut surface = FaceSurface::new();
                let plan = self.uv_plans[q.face as usize].as_ref();
                surface.load(uv, self.scheme, FaceId(q.face), plan);
                Some(UvSample::from(surface.eval_located(
                    sub,
                    s,
                    t,
                    Derivatives::First,
                )))
            }
        })
    }

    /// The limit surface at every query, in parallel (`out[i]` for `queries[i]`; the lengths
    /// must agree). Queries are grouped by face, and each face's neighbourhood is refined once
    /// for all its points; nothing is allocated per point. Every query is checked first: the
    /// first bad one is the error, and then nothing is written.
    pub fn evaluate_many(
        &self,
        queries: &[Query],
        d: Derivatives,
        out: &mut [Sample],
    ) -> Result<(), EvalError> {
        self.evaluate_many_as(queries, d, out, |s| s)
    }

    /// [`Evaluator::evaluate_many`] keeping `conv` of each sample: what a caller keeps of many
    /// points (a position and a normal in `f32`) without a full [`Sample`] apiece.
    pub(crate) fn evaluate_many_as<T: Clone + Default + Send>(
        &self,
        queries: &[Query],
        d: Derivatives,
        out: &mut [T],
        conv: impl Fn(Sample) -> T + Sync,
    ) -> Result<(), EvalError> {
        assert_eq!(
            queries.len(),
            out.len(),
            "evaluate_many: one output per query"
        );
        let located = self.locate_all(queries)?;
        batch(
            (self.mesh, &self.plans),
            self.scheme,
            (queries, &located),
            d,
            out,
            conv,
        );
        Ok(())
    }

    /// [`Evaluator::evaluate_many`] for the UVs; `false` (nothing written) without UVs.
    pub fn evaluate_uv_many(
        &self,
        queries: &[Query],
        out: &mut [UvSample],
    ) -> Result<bool, EvalError> {
        assert_eq!(
            queries.len(),
            out.len(),
            "evaluate_uv_many: one output per query"
        );
        let located = self.locate_all(queries)?;
        let uv = match &self.uv {
            None => return Ok(false),
            Some(Uvs::Linear) => {
                for ((o, q), &(sub, s, t)) in out.iter_mut().zip(queries).zip(&located) {
                    *o = self.linear(q.face, sub, s, t);
                }
                return Ok(true);
            }
            Some(Uvs::Cage(uv)) => uv,
        };
        batch(
            (uv, &self.uv_plans),
            self.scheme,
            (queries, &located),
            Derivatives::First,
            out,
            UvSample::from,
        );
        Ok(true)
    }

    fn linear(&self, face: u32, sub: usize, s: f64, t: f64) -> UvSample {
        let [uv, du, dv] = linear_uv(self.mesh, FaceId(face), self.scheme, sub, s, t);
        let k = Domain::of(self.scheme, self.mesh.face_size(FaceId(face))).derivative_scale();
        UvSample {
            uv,
            du: du * k,
            dv: dv * k,
        }
    }

    fn locate_all(&self, queries: &[Query]) -> Result<Vec<(usize, f64, f64)>, EvalError> {
        queries.iter().map(|&q| self.locate(q)).collect()
    }
}

/// `n` random queries on `eval`'s cage, reproducible from `seed`: faces uniformly among
/// those that are not holes, `(u, v)` uniformly in each face's domain ([`Domain::sample`]).
/// Empty when every face is a hole.
pub fn random_queries(eval: &Evaluator<'_>, n: usize, seed: u64) -> Vec<Query> {
    let faces: Vec<u32> = (0..eval.mesh.num_faces() as u32)
        .filter(|&f| !eval.mesh.is_hole(FaceId(f)))
        .collect();
    if faces.is_empty() {
        return Vec::new();
    }
    // SplitMix64 (Steele, Lea and Flood 2014).
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
    (0..n)
        .map(|_| {
            let face = faces[((unit() * faces.len() as f64) as usize).min(faces.len() - 1)];
            let domain = Domain::of(eval.scheme, eval.mesh.face_size(FaceId(face)));
            let [u, v] = domain.sample([unit(), unit(), unit()]);
            Query { face, u, v }
        })
        .collect()
}

impl From<Sample> for UvSample {
    fn from(s: Sample) -> UvSample {
        UvSample {
            uv: s.position.truncate(),
            du: s.du.truncate(),
            dv: s.dv.truncate(),
        }
    }
}

impl FaceSurface {
    /// The limit surface at `(u, v)` of this face.
    pub fn evaluate(&mut self, u: f64, v: f64, d: Derivatives) -> Result<Sample, EvalError> {
        let domain = self.domain();
        let (sub, s, t) = domain
            .locate(u, v)
            .ok_or_else(|| EvalError::OutsideDomain {
                face: self.face(),
                u,
                v,
                domain: domain.describe(),
            })?;
        Ok(self.eval_located(sub, s, t, d))
    }
}

/// Evaluates located queries of `mesh` in parallel, one task per face's run of queries.
fn batch<T: Clone + Default + Send>(
    (mesh, plans): (&Mesh, &[Option<[u32; 16]>]),
    scheme: Scheme,
    (queries, located): (&[Query], &[(usize, f64, f64)]),
    d: Derivatives,
    out: &mut [T],
    conv: impl Fn(Sample) -> T + Sync,
) {
    let sorted = queries.windows(2).all(|w| w[0].face <= w[1].face);
    let order: Vec<u32> = if sorted {
        Vec::new()
    } else {
        let mut o: Vec<u32> = (0..queries.len() as u32).collect();
        o.sort_by_key(|&i| queries[i as usize].face);
        o
    };
    let at = |i: usize| if sorted { i } else { order[i] as usize };
    // Runs of one face, in sorted order.
    let mut runs = Vec::new();
    let mut start = 0;
    for i in 1..=queries.len() {
        if i == queries.len() || queries[at(i)].face != queries[at(start)].face {
            runs.push(start..i);
            start = i;
        }
    }
    let mut tmp = if sorted {
        Vec::new()
    } else {
        vec![T::default(); queries.len()]
    };
    let target: &mut [T] = if sorted { out } else { &mut tmp };
    let mut slices = Vec::with_capacity(runs.len());
    let mut rest = target;
    for r in &runs {
        let (a, b) = rest.split_at_mut(r.len());
        slices.push((r.clone(), a));
        rest = b;
    }
    slices
        .into_par_iter()
        .for_each_init(FaceSurface::new, |surface, (range, slice)| {
            let face = queries[at(range.start)].face;
            surface.load(mesh, scheme, FaceId(face), plans[face as usize].as_ref());
            for (o, i) in slice.iter_mut().zip(range) {
                let (sub, s, t) = located[at(i)];
                *o = conv(surface.eval_located(sub, s, t, d));
            }
        });
    if !sorted {
        for (i, s) in tmp.into_iter().enumerate() {
            out[order[i] as usize] = s;
        }
    }
}
