//! `subdiv bench animate`: the per-frame update of a moving cage, what a renderer of an animated
//! character pays each frame once the tessellation is set up.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use subdiv::mesh::{Mesh, UsdReadOptions, UsdStageReader, is_usd_path, sway};
use subdiv::rules::{LimitMesh, Request, Scheme};
use subdiv::stencil::StencilTessellator;
use subdiv::{DynamicSubdivision, mesh::glam::Vec3};

use crate::adaptive_args::AdaptiveArgs;
use crate::camera_args::CameraArgs;
use crate::choices::SchemeName;

/// Frames of a cage that moves without an authored animation.
const SWAY_FRAMES: usize = 48;

#[derive(clap::Args, Debug)]
pub struct BenchAnimateArgs {
    /// Input cage: a USD stage whose points or transforms are time-sampled (its frames: the
    /// time codes of its range, one apart), or any other cage (OBJ, static USD), swayed by a
    /// wave travelling up its bounding box (subdiv_mesh::sway).
    pub input: PathBuf,
    /// The USD mesh prim to read (e.g. /World/Body).
    #[arg(long, value_name = "PATH")]
    pub prim: Option<String>,
    /// Frames to time [default: the stage's frames, else 48]; an animated stage's range is
    /// played again from its start when it has fewer.
    #[arg(long)]
    pub frames: Option<usize>,
    /// Uniform depth (the default without a camera: 3); with a camera (--eye or
    /// --eye-relative) or an adaptive flag and no --depth, the adaptive tessellation.
    #[arg(long)]
    pub depth: Option<subdiv::rules::Depth>,
    /// Subdivision scheme [default: the USD subdivisionScheme, else catmull-clark].
    #[arg(long, value_enum)]
    pub scheme: Option<SchemeName>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
    #[command(flatten)]
    pub limit: crate::limit_args::LimitArgs,
}

/// Where the frames' cages come from.
enum Frames {
    /// An animated stage, read at `start + (i mod count)`.
    Stage {
        reader: UsdStageReader,
        start: f64,
        count: usize,
    },
    /// The first cage swayed ([`sway`]) over `count` frames.
    Sway { rest: Vec<Vec3>, count: usize },
}

impl Frames {
    /// The time code (stage) or frame number (sway) of frame `i`.
    fn time(&self, i: usize) -> f64 {
        match self {
            Frames::Stage { start, count, .. } => start + (i % count) as f64,
            Frames::Sway { count, .. } => (i % count) as f64,
        }
    }

    /// Writes frame `i`'s cage into `cage` (replaced when its topology differs).
    fn cage(&self, i: usize, cage: &mut Mesh, scratch: &mut Vec<Vec3>) -> anyhow::Result<()> {
        match self {
            Frames::Stage { reader, .. } => {
                *cage = reader.read_at(Some(self.time(i)))?.mesh;
            }
            Frames::Sway { rest, count } => {
                sway(rest, i % count, *count, scratch);
                cage.positions_mut().copy_from_slice(scratch);
            }
        }
        Ok(())
    }
}

/// The tessellation timed each frame.
enum Tessellation {
    Uniform(Box<StencilTessellator>),
    Adaptive(Box<DynamicSubdivision>, subdiv::mesh::Camera),
}

impl Tessellation {
    /// The frame's update for `cage`; the surface.
    fn update(&mut self, cage: &Mesh) -> anyhow::Result<&LimitMesh> {
        match self {
            Tessellation::Uniform(t) => Ok(t.update(cage)?),
            Tessellation::Adaptive(node, camera) => {
                if node.mesh().same_topology(cage) {
                    node.set_positions(cage.positions())?;
                } else {
                    let (scheme, params) = (node.scheme(), *node.params());
                    **node = DynamicSubdivision::with_scheme(cage.clone(), scheme, params)?;
                }
                Ok(node.update(camera, None)?.surface())
            }
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

pub fn run(a: &BenchAnimateArgs) -> anyhow::Result<ExitCode> {
    let threads = a.threads.unwrap_or_else(rayon::current_num_threads);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    // Everything on a thread of the pool, as a renderer thread of that pool would run it (the
    // stage reader stays on the thread that opened it).
    pool.install(|| animate(a, threads))
}

fn animate(a: &BenchAnimateArgs, threads: usize) -> anyhow::Result<ExitCode> {
    let label = a.input.display().to_string();
    let adaptive = a
        .adaptive
        .wants_adaptive(a.depth.is_some(), a.camera.has_camera(), &[])?;
    let cage = crate::load::load_cage(&a.input, a.split_nonmanifold, a.prim.as_deref(), None)?;
    let scheme = crate::load::cage_scheme(&a.input, &cage, a.scheme.map(Scheme::from))?;
    let mut mesh = cage.mesh;
    let frames = frames_of(a, &mesh)?;
    let count = a.frames.unwrap_or(match &frames {
        Frames::Stage { count, .. } | Frames::Sway { count, .. } => *count,
    });
    anyhow::ensure!(count >= 1, "--frames must be at least 1");
    let mut scratch = Vec::new();
    frames.cage(0, &mut mesh, &mut scratch)?;
    let t0 = Instant::now();
    let (mut tess, what) = if adaptive {
        let max_depth = a.adaptive.max_depth();
        let request = Request::Adaptive { scheme, max_depth };
        a.limit.check(&mesh, request, &label)?;
        let camera = a.camera.camera(&mesh);
        let node = a
            .adaptive
            .node(mesh.clone(), scheme)
            .context(label.clone())?;
        let what = format!("adaptive max_depth={max_depth}");
        (Tessellation::Adaptive(Box::new(node), camera), what)
    } else {
        let depth = a.depth.unwrap_or(3);
        a.limit
            .check(&mesh, Request::Uniform { scheme, depth }, &label)?;
        let t = StencilTessellator::new(&mesh, scheme, depth).context(label.clone())?;
        (Tessellation::Uniform(Box::new(t)), format!("depth={depth}"))
    };
    let setup = t0.elapsed().as_secs_f64();
    // What computes a uniform frame: the stencil table, or the slates every frame.
    let path = match &tess {
        Tessellation::Uniform(t) if t.stencils().is_some() => " path=stencils",
        Tessellation::Uniform(_) => " path=slates",
        Tessellation::Adaptive(..) => "",
    };
    let source = match &frames {
        Frames::Stage { .. } => "stage",
        Frames::Sway { .. } => "sway",
    };
    out!(
        "input={label} scheme={} {what} threads={threads} frames={count} source={source} setup_ms={:.3}{path}",
        crate::choices::value_name(&SchemeName::from(scheme)),
        setup * 1e3
    );
    let bar = crate::progress::bar(count as u64, "frames");
    let (mut times, mut points) = (Vec::with_capacity(count), Vec::with_capacity(count));
    for i in 0..count {
        frames.cage(i, &mut mesh, &mut scratch)?;
        let t = Instant::now();
        let surface = tess.update(&mesh).context(label.clone())?;
        let dt = t.elapsed().as_secs_f64();
        std::hint::black_box(surface);
        out!(
            "frame={i} time={} update_ms={:.3} points={} faces={} topology_written={}",
            frames.time(i),
            dt * 1e3,
            surface.num_vertices(),
            surface.num_faces(),
            u8::from(surface.topology_written())
        );
        times.push(dt);
        points.push(surface.num_vertices() as f64);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let med = median(times);
    out!(
        "frames={count} update_ms_median={:.3} points_per_s={:.0}",
        med * 1e3,
        median(points) / med
    );
    Ok(ExitCode::SUCCESS)
}

/// The frames of `a.input`: an animated stage's time codes, else `mesh` swayed.
fn frames_of(a: &BenchAnimateArgs, mesh: &Mesh) -> anyhow::Result<Frames> {
    if is_usd_path(&a.input) {
        let opts = UsdReadOptions {
            prim: a.prim.clone(),
            split_nonmanifold_vertices: a.split_nonmanifold,
            time: None,
        };
        let reader = UsdStageReader::open(&a.input, &opts)?;
        let time = reader.time()?;
        if let (true, Some((start, end))) = (time.is_animated(), time.range()) {
            let count = ((end - start).floor() as usize).saturating_add(1);
            return Ok(Frames::Stage {
                reader,
                start,
                count,
            });
        }
    }
    Ok(Frames::Sway {
        rest: mesh.positions().to_vec(),
        count: a.frames.unwrap_or(SWAY_FRAMES).max(1),
    })
}
