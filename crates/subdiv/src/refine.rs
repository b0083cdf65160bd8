//! DoI-driven adaptive Loop subdivision (Isenberg, Hartmann & König 2003): a Degree of Interest
//! from `subdiv-doi` chooses the faces, `subdiv-redgreen` refines them with red-green closure.

use std::time::Instant;

use subdiv_doi::{Aggregate, Doi, DoiContext, DoiError, face_values, select};
use subdiv_mesh::Mesh;
pub use subdiv_redgreen::Balance;
use subdiv_redgreen::{AdaptiveMesh, RedGreenError, StepStats, loop_step_with};
use thiserror::Error;

/// What can go wrong in DoI-driven refinement.
#[derive(Debug, Error)]
pub enum RefineError {
    /// The DoI could not be evaluated.
    #[error(transparent)]
    Doi(#[from] DoiError),
    /// The adaptive Loop step refused its input.
    #[error(transparent)]
    RedGreen(#[from] RedGreenError),
    /// Every face refined at every step would not fit in this machine's memory: refused before
    /// the first step, with the size asked for ([`subdiv_rules::budget`]: an upper bound).
    #[error(transparent)]
    OutputTooLarge(#[from] subdiv_rules::OutputTooLarge),
    /// A step would produce too many triangles.
    #[error("step {step} would produce {faces} triangles (limit {limit})")]
    TooLarge {
        /// 1-based step.
        step: u32,
        /// Triangles it would produce.
        faces: u64,
        /// The limit.
        limit: u64,
    },
}

/// Parameters of an adaptive refinement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefineOptions {
    /// Faces with a value above this are refined.
    pub threshold: f32,
    /// Number of steps.
    pub steps: u32,
    /// How edge or vertex values become face values.
    pub aggregate: Aggregate,
    /// Level balancing before the red-green closure ([`Balance::Vertex`]: the smallest angle
    /// does not decay; [`Balance::None`]: the paper's plain closure, fewest triangles).
    pub balance: Balance,
}

/// The result of [`refine_adaptive`].
#[derive(Clone, Debug)]
pub struct Refined {
    /// The final mesh.
    pub mesh: AdaptiveMesh,
    /// One entry per step.
    pub steps: Vec<StepStats>,
}

/// Refines `mesh` adaptively (Isenberg, Hartmann & König 2003, §3): before every step the DoI is
/// evaluated on the current mesh (with `ctx.step` and `ctx.steps` set), the faces above the
/// threshold are selected, and one [`subdiv_redgreen::loop_step`] is taken. A refinement whose
/// bound (every face refined at every step: `4^steps` times the triangles) is beyond this
/// machine's memory is refused first with [`RefineError::OutputTooLarge`].
///
/// ```
/// use subdiv::{refine_adaptive, Balance, RefineOptions};
/// use subdiv_doi::{Aggregate, Dihedral, DoiContext};
/// use subdiv_mesh::{parse_obj, Mesh};
/// let tet = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")?)?;
/// let opts = RefineOptions { threshold: 30.0, steps: 2, aggregate: Aggregate::Max, balance: Balance::Vertex };
/// let r = refine_adaptive(&tet, &Dihedral, &DoiContext::default(), &opts)?;
/// assert_eq!(r.steps.len(), 2);
/// assert!(r.mesh.mesh.num_faces() <= 4 * 16);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn refine_adaptive(
    mesh: &Mesh,
    doi: &dyn Doi,
    ctx: &DoiContext,
    opts: &RefineOptions,
) -> Result<Refined, RefineError> {
    if opts.threshold.is_nan() {
        return Err(DoiError::NonFinite {
            what: "threshold",
            value: opts.threshold,
        }
        .into());
    }
    subdiv_rules::Budget::machine()
        .check(mesh, subdiv_rules::Request::Refine { steps: opts.steps })?;
    let mut cur = AdaptiveMesh::new(mesh.clone())?;
    let mut steps = Vec::with_capacity(opts.steps as usize);
    let (mut scratch, mut values, mut sel) = (Vec::new(), Vec::new(), Vec::new());
    for s in 0..opts.steps {
        let t0 = Instant::now();
        let c = DoiContext {
            step: s,
            steps: opts.steps,
            ..*ctx
        };
        face_values(
            doi,
            &cur.mesh,
            &c,
            opts.aggregate,
            &mut scratch,
            &mut values,
        )?;
        select(&values, opts.threshold, &mut sel);
        let t1 = Instant::now();
        let (next, mut st) = loop_step_with(&cur, &sel, opts.balance).map_err(|e| match e {
            RedGreenError::TooLarge { faces, limit } => RefineError::TooLarge {
                step: s + 1,
                faces,
                limit,
            },
            e => RefineError::RedGreen(e),
        })?;
        st.select_seconds = (t1 - t0).as_secs_f64();
        st.refine_seconds = t1.elapsed().as_secs_f64();
        steps.push(st);
        cur = next;
    }
    Ok(Refined { mesh: cur, steps })
}

/// Adaptive refinement over frames: static DoIs are evaluated once and their result is cached;
/// view-dependent DoIs are re-evaluated (and the mesh re-refined) for every frame.
///
/// ```
/// use subdiv::{Balance, RefineOptions, Refiner};
/// use subdiv_doi::{Aggregate, Dihedral, DoiContext};
/// use subdiv_mesh::{parse_obj, Mesh};
/// let tet = Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")?)?;
/// let opts = RefineOptions { threshold: 30.0, steps: 1, aggregate: Aggregate::Max, balance: Balance::Vertex };
/// let mut r = Refiner::new(tet, Box::new(Dihedral), opts)?;
/// r.frame(&DoiContext::default())?;
/// r.frame(&DoiContext::default())?;
/// assert_eq!(r.evaluations(), 1); // static: cached after the first frame
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Refiner {
    base: Mesh,
    doi: Box<dyn Doi>,
    opts: RefineOptions,
    cached: Option<Refined>,
    evaluations: usize,
}

impl Refiner {
    /// A refiner for `base` (a triangle mesh) with `doi`.
    pub fn new(base: Mesh, doi: Box<dyn Doi>, opts: RefineOptions) -> Result<Refiner, RefineError> {
        base.check_triangles().map_err(RedGreenError::from)?;
        Ok(Refiner {
            base,
            doi,
            opts,
            cached: None,
            evaluations: 0,
        })
    }

    /// The refined mesh for this frame's context.
    pub fn frame(&mut self, ctx: &DoiContext) -> Result<&Refined, RefineError> {
        if self.doi.is_view_dependent() || self.cached.is_none() {
            let r = refine_adaptive(&self.base, self.doi.as_ref(), ctx, &self.opts)?;
            self.evaluations += 1;
            self.cached = Some(r);
        }
        Ok(self.cached.as_ref().expect("set above"))
    }

    /// How many times the refinement was computed.
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use subdiv_mesh::{Camera, parse_obj};

    const OCTAHEDRON: &str = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
        f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

    #[test]
    fn refiner_caches_static_and_reevaluates_view_dependent() {
        let m = Mesh::from_soup(&parse_obj(OCTAHEDRON).unwrap()).unwrap();
        let opts = RefineOptions {
            threshold: 0.5,
            steps: 2,
            aggregate: Aggregate::Max,
            balance: Balance::Vertex,
        };
        let mut r = Refiner::new(m.clone(), Box::new(subdiv_doi::Silhouette), opts).unwrap();
        let cam = |z: f32| Camera::new(Vec3::new(0.3, 0.2, z), Vec3::ZERO, Vec3::Y, 30.0, 64, 64);
        let n1 = r
            .frame(&DoiContext::with_camera(cam(10.0)))
            .unwrap()
            .mesh
            .mesh
            .num_faces();
        let n2 = r
            .frame(&DoiContext::with_camera(cam(-10.0)))
            .unwrap()
            .mesh
            .mesh
            .num_faces();
        assert_eq!(r.evaluations(), 2);
        assert!(n1 > 8 && n2 > 8);
        let mut r = Refiner::new(
            m,
            Box::new(subdiv_doi::Dihedral),
            RefineOptions {
                threshold: 30.0,
                ..opts
            },
        )
        .unwrap();
        for _ in 0..3 {
            r.frame(&DoiContext::default()).unwrap();
        }
        assert_eq!(r.evaluations(), 1);
    }

    #[test]
    fn bad_input() {
        let a =
            AdaptiveMesh::new(Mesh::from_soup(&parse_obj(OCTAHEDRON).unwrap()).unwrap()).unwrap();
        let m = a.mesh.clone();
        let opts = RefineOptions {
            threshold: f32::NAN,
            steps: 1,
            aggregate: Aggregate::Max,
            balance: Balance::Vertex,
        };
        assert!(matches!(
            refine_adaptive(&m, &subdiv_doi::Dihedral, &DoiContext::default(), &opts),
            Err(RefineError::Doi(DoiError::NonFinite { .. }))
        ));
        let opts = RefineOptions {
            threshold: 0.5,
            steps: 1,
            aggregate: Aggregate::Max,
            balance: Balance::Vertex,
        };
        assert!(matches!(
            refine_adaptive(&m, &subdiv_doi::Silhouette, &DoiContext::default(), &opts),
            Err(RefineError::Doi(DoiError::NeedsCamera {
                doi: "silhouette"
            }))
        ));
        let quad =
            Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap())
                .unwrap();
        let e = Refiner::new(quad, Box::new(subdiv_doi::Dihedral), opts)
            .err()
            .unwrap();
        assert!(e.to_string().contains("face 0 has 4 vertices"), "{e}");
    }
}
