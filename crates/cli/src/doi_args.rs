//! The DoI flags, declared once: `--doi NAME --threshold T --focus NAME` (every DoI-driven
//! command) and the refinement flags `--steps --triangulate --skeleton --hip --aggregate`
//! (`refine`, `render --doi`, `view --doi`). Library errors become the flag-naming messages.

use anyhow::anyhow;
use glam::Vec3;
use subdiv::doi::DoiKind;
use subdiv::mesh::Mesh;
use subdiv::{DoiOptions, DoiSetup, DoiSetupError};

use crate::camera_args::parse_vec3;
use crate::choices::{AggregateName, DoiName};

/// `--doi NAME`, `--threshold T`, `--focus NAME`: which DoI, and what it needs.
#[derive(clap::Args, Debug, Clone)]
pub struct DoiChoice {
    /// The Degree-of-Interest function.
    #[arg(long)]
    pub doi: Option<DoiName>,
    /// Refine faces whose DoI exceeds this (default: the paper's figure value: view-angle 70
    /// (degrees from head-on), silhouette 0.5, dihedral 30 (degrees), haptic 1 (either criterion beyond
    /// its tolerance; 0.5 with --hip), focus 0).
    #[arg(long, allow_hyphen_values = true)]
    pub threshold: Option<f32>,
    /// Focus objects for --doi focus: an OBJ group or object name, `NAME` (interest 1) or
    /// `NAME=VALUE` (its own interest, eq. (7)'s DoI(o)); repeatable.
    #[arg(long = "focus", value_name = "NAME[=VALUE]")]
    pub focus: Vec<String>,
}

/// The DoI choice and the flags of a DoI-driven adaptive Loop refinement.
#[derive(clap::Args, Debug, Clone)]
pub struct DoiArgs {
    #[command(flatten)]
    pub choice: DoiChoice,
    /// Number of adaptive Loop steps.
    #[arg(long, default_value_t = 3)]
    pub steps: u32,
    /// Split quads and n-gons into triangles first (Loop subdivision needs triangles).
    #[arg(long)]
    pub triangulate: bool,
    /// Skeleton polyline for --doi focus (points as `v X Y Z` or `X Y Z` lines): `FILE` for
    /// every focus object, or `NAME=FILE` for one; repeatable. Objects without one are measured
    /// from their computed curve skeleton (level-set diagram).
    #[arg(long, value_name = "[NAME=]FILE")]
    pub skeleton: Vec<String>,
    /// Haptic interaction point: with --doi haptic, refine the triangle closest to it (the point
    /// is snapped to the closest surface point) and its one-neighbourhood instead of using the
    /// Clough-Tocher criteria.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub hip: Option<Vec3>,
    /// How edge or vertex DoI values become face values.
    #[arg(long, value_enum, default_value = "max")]
    pub aggregate: AggregateName,
    /// Skip level balancing: only the paper's red-green closure (fewer triangles, but the
    /// smallest angle decays with the steps).
    #[arg(long)]
    pub no_balance: bool,
}

impl DoiArgs {
    /// The DoI chosen, if any.
    pub fn kind(&self) -> Option<DoiKind> {
        self.choice.doi.map(DoiKind::from)
    }

    /// Refuses DoI options without the DoI that uses them.
    pub fn check(&self) -> anyhow::Result<()> {
        let (focus, skeleton) = (&self.choice.focus, &self.skeleton);
        subdiv::check_doi_options(self.kind(), focus, skeleton, self.hip)
            .map_err(|e| doi_error(e, ""))?;
        if self.kind().is_none() && self.aggregate != AggregateName::Max {
            anyhow::bail!("--aggregate needs --doi NAME");
        }
        Ok(())
    }

    /// The refinement of `cage` (read from `input`) these flags describe; `--doi` must be given.
    pub fn setup(&self, cage: Mesh, input: &str) -> anyhow::Result<DoiSetup> {
        let kind = self.kind().ok_or_else(|| anyhow!("--doi NAME is needed"))?;
        let options = DoiOptions {
            kind,
            threshold: self.choice.threshold,
            steps: self.steps,
            aggregate: self.aggregate.into(),
            triangulate: self.triangulate,
            focus: self.choice.focus.clone(),
            skeletons: self.skeleton.clone(),
            hip: self.hip,
            balance: if self.no_balance {
                subdiv::Balance::None
            } else {
                subdiv::Balance::Vertex
            },
        };
        DoiSetup::new(cage, &options).map_err(|e| doi_error(e, input))
    }
}

/// A DoI set-up error as the command line reports it: flag names, the input's name in front.
pub fn doi_error(e: DoiSetupError, input: &str) -> anyhow::Error {
    match e {
        DoiSetupError::FocusWithoutFocusDoi => anyhow!("--focus and --skeleton need --doi focus"),
        DoiSetupError::HipWithoutHapticDoi => anyhow!("--hip needs --doi haptic"),
        DoiSetupError::Triangulate(e) => {
            anyhow::Error::new(e).context(format!("{input}: triangulating"))
        }
        DoiSetupError::NotTriangles { face, size } => anyhow!(
            "{input}: face {face} has {size} vertices; Loop subdivision needs triangles (pass --triangulate to split quads and n-gons)"
        ),
        DoiSetupError::Focus(e) => anyhow::Error::new(e).context(format!("{input}: --focus")),
        DoiSetupError::Threshold => anyhow!("--threshold must be a finite number"),
        e => e.into(),
    }
}
