//! `subdiv bench`: throughput measurements (medians of repeated runs).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use subdiv::rules::{Request, Scheme};
use subdiv::slate::{
    BilinearLayout, PatchLayout, TriLayout, slate_bytes_per_thread, tessellate_bilinear_into,
    tessellate_layout, tessellate_layout_into, tessellate_tri, tessellate_tri_layout_into,
    tri_slate_bytes_per_thread,
};

use crate::choices::SchemeName;

#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchWhat,
}

#[derive(clap::Subcommand, Debug)]
pub enum BenchWhat {
    /// Slate tessellation throughput of a frame: limit points, normals and indices written each
    /// run (`--points-only`: points and normals into reused indices). Last line:
    /// `limit_points_per_s=<f> patches_per_s=<f> slate_bytes_per_thread=<n> timed=<what>`.
    Tessellate(BenchTessellateArgs),
    /// Frame rate of the paper's Fig. 12 scene rendered headless, one line per frame:
    /// `frame=<i> fps=<f> triangles=<n> maxsd=<cap> patches=<n0>,<n1>,..` (patches per depth).
    Framerate(crate::bench_framerate::BenchFramerateArgs),
    /// Image error against the true surface (a deeper uniform tessellation): uniform depths
    /// 0..=max, curvature-adaptive and pixel error 2, 1, 0.5; last lines, one per configuration:
    /// `config=<name> triangles=<n> silhouette_px_max=<f> silhouette_px_p99=<f>
    /// shading_deg_p99=<f> update_ms=<f> render_ms=<f> shading_deg_p99_off_lines=<f>`.
    Quality(crate::bench_quality::BenchQualityArgs),
    /// Per-frame update of a moving cage (an animated stage's frames, or any cage swayed): the
    /// layout is kept while the topology stays and points and normals are rewritten. One line a
    /// frame, `frame=<i> time=<t> update_ms=<f> points=<n> faces=<n> topology_written=<0|1>`,
    /// then `frames=<n> update_ms_median=<f> points_per_s=<f>`.
    Animate(crate::bench_animate::BenchAnimateArgs),
    /// Exact evaluation throughput at (face, u, v) points (`subdiv evaluate`'s, batched).
    Evaluate(crate::bench_evaluate::BenchEvaluateArgs),
}

#[derive(clap::Args, Debug)]
pub struct BenchTessellateArgs {
    /// Input cage.
    pub input: PathBuf,
    /// Uniform depth.
    #[arg(long, default_value_t = 5)]
    pub depth: subdiv::rules::Depth,
    /// Subdivision scheme: Catmull-Clark on the quad slates, Loop on the triangular slates
    /// [default: the USD subdivisionScheme, else catmull-clark].
    #[arg(long, value_enum)]
    pub scheme: Option<SchemeName>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Timed runs (the median is reported).
    #[arg(long, default_value_t = 15)]
    pub runs: usize,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
    /// Time only limit points and normals, into output whose indices were written once before
    /// the timed runs (a renderer that keeps the index buffer of an unchanged layout); by
    /// default every run writes the indices too, as each new tessellation does.
    #[arg(long)]
    pub points_only: bool,
    /// USD: the time code to read the stage at (time samples interpolated as USD does)
    /// [default: default values, else the earliest time samples].
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub time: Option<f64>,
    /// Also time a plain store loop over a buffer of the frame's output size (points, normals
    /// and indices), on one thread, the same number of runs: the machine's write bandwidth the
    /// tessellation's own is measured against, printed as `store_bytes_per_s=<f>
    /// output_bytes=<n>` on a line of its own.
    #[arg(long)]
    pub store_bandwidth: bool,
    #[command(flatten)]
    pub limit: crate::limit_args::LimitArgs,
}

impl BenchTessellateArgs {
    /// What one timed run writes: the `timed=` field of the output lines.
    fn timed(&self) -> &'static str {
        if self.points_only {
            "points+normals"
        } else {
            "points+normals+indices"
        }
    }
}

pub fn run(a: &BenchArgs) -> anyhow::Result<ExitCode> {
    match &a.what {
        BenchWhat::Tessellate(t) => bench_tessellate(t),
        BenchWhat::Evaluate(e) => crate::bench_evaluate::run(e),
        BenchWhat::Framerate(f) => crate::bench_framerate::run(f),
        BenchWhat::Quality(q) => crate::bench_quality::run(q),
        BenchWhat::Animate(m) => crate::bench_animate::run(m),
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Median bytes per second of `runs` plain stores of a `bytes`-sized buffer (one thread): the
/// write bandwidth of the memory the output lands in, which bounds any tessellator.
fn store_bandwidth(bytes: usize, runs: usize) -> f64 {
    let mut buf = vec![0u64; bytes.div_ceil(8).max(1)];
    let mut times = Vec::with_capacity(runs);
    for k in 0..=runs {
        let t = Instant::now();
        buf.fill(k as u64);
        std::hint::black_box(&mut buf);
        if k > 0 {
            times.push(t.elapsed().as_secs_f64());
        }
    }
    (buf.len() * 8) as f64 / median(times)
}

/// `--store-bandwidth`: the line `store_bytes_per_s=<f> output_bytes=<n>` for `out`.
fn print_store_bandwidth(a: &BenchTessellateArgs, out: &subdiv::LimitMesh) {
    if a.store_bandwidth {
        let bytes = out.num_vertices() * 24 + out.face_indices().len() * 4;
        out!(
            "store_bytes_per_s={:.0} output_bytes={bytes}",
            store_bandwidth(bytes, a.runs)
        );
    }
}

fn bench_tessellate(a: &BenchTessellateArgs) -> anyhow::Result<ExitCode> {
    let cage = crate::load::load_cage(&a.input, a.split_nonmanifold, None, a.time)?;
    let scheme = crate::load::cage_scheme(&a.input, &cage, a.scheme.map(Scheme::from))?;
    let mesh = cage.mesh;
    anyhow::ensure!(a.depth >= 1, "--depth must be at least 1");
    anyhow::ensure!(a.runs >= 1, "--runs must be at least 1");
    let depth = a.depth;
    let input = a.input.display().to_string();
    a.limit
        .check(&mesh, Request::Uniform { scheme, depth }, &input)?;
    let threads = a.threads.unwrap_or_else(rayon::current_num_threads);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    if scheme == Scheme::Loop {
        return bench_loop(a, &mesh, &pool);
    }
    if scheme == Scheme::Bilinear {
        return bench_bilinear(a, &mesh, &pool);
    }
    let t0 = Instant::now();
    let layout = PatchLayout::new(&mesh, a.depth)
        .map_err(|e| anyhow::anyhow!("{}: {e}", a.input.display()))?;
    let setup = t0.elapsed().as_secs_f64();
    // Warm-up, then timed runs into the same output buffers: each run writes points and normals,
    // and the indices too (its faces removed first) unless `--points-only` (a renderer keeping
    // an index buffer). The runs are timed inside the pool, as a renderer thread of that pool would call the tessellator:
    // the hand-off from this thread into the pool (a wake-up and a sleep) is not measured.
    let bar = crate::progress::bar(a.runs as u64 + 1, "runs");
    let out_times = pool.install(|| -> anyhow::Result<_> {
        let mut out = tessellate_layout(&mesh, &layout)?;
        bar.inc(1);
        let mut times = Vec::with_capacity(a.runs);
        for _ in 0..a.runs {
            if !a.points_only {
                out.clear_faces();
            }
            let t = Instant::now();
            tessellate_layout_into(&mesh, &layout, &mut out)?;
            times.push(t.elapsed().as_secs_f64());
            std::hint::black_box(&out);
            bar.inc(1);
        }
        Ok((out, times))
    });
    bar.finish_and_clear();
    let (out, times) = out_times?;
    let med = median(times.clone());
    let points = out.num_vertices() as f64;
    let patches = layout.num_patches() as f64;
    out!(
        "input={} depth={} threads={} patches={} limit_points={} quads={} setup_ms={:.3} median_ms={:.3} min_ms={:.3} timed={}",
        a.input.display(),
        a.depth,
        threads,
        layout.num_patches(),
        out.num_vertices(),
        out.num_faces(),
        setup * 1e3,
        med * 1e3,
        times.iter().copied().fold(f64::INFINITY, f64::min) * 1e3,
        a.timed()
    );
    out!(
        "limit_points_per_s={:.0} patches_per_s={:.0} slate_bytes_per_thread={} timed={}",
        points / med,
        patches / med,
        slate_bytes_per_thread(a.depth, layout.max_valence()),
        a.timed()
    );
    print_store_bandwidth(a, &out);
    Ok(ExitCode::SUCCESS)
}

/// `bench tessellate --scheme bilinear`: the bilinear patches, the same lines (no slates:
/// `slate_bytes_per_thread=0`).
fn bench_bilinear(
    a: &BenchTessellateArgs,
    mesh: &subdiv::mesh::Mesh,
    pool: &rayon::ThreadPool,
) -> anyhow::Result<ExitCode> {
    let t0 = Instant::now();
    let layout = BilinearLayout::new(mesh, a.depth)
        .map_err(|e| anyhow::anyhow!("{}: {e}", a.input.display()))?;
    let setup = t0.elapsed().as_secs_f64();
    let mut out = subdiv::LimitMesh::default();
    let times = pool.install(|| -> anyhow::Result<_> {
        tessellate_bilinear_into(mesh, &layout, &mut out)?;
        let mut times = Vec::with_capacity(a.runs);
        for _ in 0..a.runs {
            if !a.points_only {
                out.clear_faces();
            }
            let t = Instant::now();
            tessellate_bilinear_into(mesh, &layout, &mut out)?;
            times.push(t.elapsed().as_secs_f64());
            std::hint::black_box(&out);
        }
        Ok(times)
    })?;
    let med = median(times.clone());
    out!(
        "input={} scheme=bilinear depth={} threads={} limit_points={} quads={} setup_ms={:.3} median_ms={:.3} min_ms={:.3} timed={}",
        a.input.display(),
        a.depth,
        pool.current_num_threads(),
        out.num_vertices(),
        out.num_faces(),
        setup * 1e3,
        med * 1e3,
        times.iter().copied().fold(f64::INFINITY, f64::min) * 1e3,
        a.timed()
    );
    out!(
        "limit_points_per_s={:.0} patches_per_s={:.0} slate_bytes_per_thread=0 timed={}",
        out.num_vertices() as f64 / med,
        layout.num_patches() as f64 / med,
        a.timed()
    );
    Ok(ExitCode::SUCCESS)
}

/// `bench tessellate --scheme loop`: the triangular slates, the same lines with `triangles=`.
fn bench_loop(
    a: &BenchTessellateArgs,
    mesh: &subdiv::mesh::Mesh,
    pool: &rayon::ThreadPool,
) -> anyhow::Result<ExitCode> {
    let threads = pool.current_num_threads();
    // Validates the cage (triangles, no doubled triangle) and warms the workers.
    let mut out = pool
        .install(|| tessellate_tri(mesh, a.depth))
        .map_err(|e| anyhow::anyhow!("{}: {e}", a.input.display()))?;
    // The setup a new cage costs: the layout alone.
    let t0 = Instant::now();
    let layout = TriLayout::new(mesh, a.depth)?;
    let setup = t0.elapsed().as_secs_f64();
    let times = pool.install(|| -> anyhow::Result<_> {
        let mut times = Vec::with_capacity(a.runs);
        for _ in 0..a.runs {
            if !a.points_only {
                out.clear_faces();
            }
            let t = Instant::now();
            tessellate_tri_layout_into(mesh, &layout, &mut out)?;
            times.push(t.elapsed().as_secs_f64());
            std::hint::black_box(&out);
        }
        Ok(times)
    })?;
    let med = median(times.clone());
    let patches = layout.patches().len();
    out!(
        "input={} scheme=loop depth={} threads={} patches={} limit_points={} triangles={} setup_ms={:.3} median_ms={:.3} min_ms={:.3} timed={}",
        a.input.display(),
        a.depth,
        threads,
        patches,
        out.num_vertices(),
        out.num_faces(),
        setup * 1e3,
        med * 1e3,
        times.iter().copied().fold(f64::INFINITY, f64::min) * 1e3,
        a.timed()
    );
    out!(
        "limit_points_per_s={:.0} patches_per_s={:.0} slate_bytes_per_thread={} timed={}",
        out.num_vertices() as f64 / med,
        patches as f64 / med,
        tri_slate_bytes_per_thread(a.depth, mesh.max_valence()),
        a.timed()
    );
    print_store_bandwidth(a, &out);
    Ok(ExitCode::SUCCESS)
}
