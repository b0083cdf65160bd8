//! `subdiv bench evaluate`: exact evaluation throughput (median of repeated runs).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::anyhow;
use subdiv::eval::{Derivatives, Evaluator, Sample};
use subdiv::rules::Scheme;

use crate::choices::{SchemeName, value_name};

#[derive(clap::Args, Debug)]
pub struct BenchEvaluateArgs {
    /// Input cage: OBJ with optional OpenSubdiv tags, or USD.
    pub input: PathBuf,
    /// Subdivision scheme [default: the USD subdivisionScheme, else catmull-clark].
    #[arg(long, value_enum)]
    pub scheme: Option<SchemeName>,
    /// The points, as `subdiv evaluate --uv` takes them.
    #[arg(
        long,
        value_name = "FILE|random:N[:SEED]",
        default_value = "random:100000"
    )]
    pub uv: String,
    /// Also the second derivatives.
    #[arg(long)]
    pub second: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Timed runs (the median is reported).
    #[arg(long, default_value_t = 9)]
    pub runs: usize,
}

/// Times `Evaluator::evaluate_many` over the points (faces refined afresh in every run); last
/// line `input=<p> scheme=<s> threads=<k> points=<n> faces=<n> derivatives=<first|second>
/// setup_ms=<f> median_ms=<f> min_ms=<f> points_per_s=<f>`.
pub fn run(a: &BenchEvaluateArgs) -> anyhow::Result<ExitCode> {
    let input = a.input.display().to_string();
    let cage = crate::load::load_cage(&a.input, false, None, None)?;
    let scheme = crate::load::cage_scheme(&a.input, &cage, a.scheme.map(Scheme::from))?;
    let t0 = Instant::now();
    let eval = Evaluator::new(&cage.mesh, scheme).map_err(|e| anyhow!("{input}: {e}"))?;
    let setup_ms = t0.elapsed().as_secs_f64() * 1e3;
    let queries = crate::evaluate::points(&eval, &a.uv)?;
    let mut faces: Vec<u32> = queries.iter().map(|q| q.face).collect();
    faces.sort_unstable();
    faces.dedup();
    let d = if a.second {
        Derivatives::Second
    } else {
        Derivatives::First
    };
    let threads = a.threads.unwrap_or_else(rayon::current_num_threads);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let mut out = vec![Sample::default(); queries.len()];
    let mut times = Vec::with_capacity(a.runs.max(1));
    for _ in 0..a.runs.max(1) {
        let t = Instant::now();
        pool.install(|| eval.evaluate_many(&queries, d, &mut out))
            .map_err(|e| anyhow!("{input}: {e}"))?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    out!(
        "input={input} scheme={} threads={threads} points={} faces={} derivatives={} setup_ms={setup_ms:.3} median_ms={median:.3} min_ms={:.3} points_per_s={:.0}",
        value_name(&SchemeName::from(scheme)),
        queries.len(),
        faces.len(),
        if a.second { "second" } else { "first" },
        times[0],
        queries.len() as f64 / (median * 1e-3)
    );
    Ok(ExitCode::SUCCESS)
}
