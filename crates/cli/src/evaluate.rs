//! `subdiv evaluate`: the exact limit surface at given parameter points.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, anyhow, bail};
use subdiv::eval::{Derivatives, Evaluator, Query, Sample, random_queries};
use subdiv::mesh::glam::DVec3;
use subdiv::rules::Scheme;

use crate::choices::{SchemeName, value_name};

#[derive(clap::Args, Debug)]
pub struct EvaluateArgs {
    /// Input cage: OBJ with optional OpenSubdiv tags, or USD (.usda, .usdc, .usdz).
    pub input: PathBuf,
    /// The USD mesh prim to read (e.g. /World/Body); every Mesh prim merged without it.
    #[arg(long, value_name = "PATH")]
    pub prim: Option<String>,
    /// USD: the time code to read the stage at (time samples interpolated as USD does)
    /// [default: default values, else the earliest time samples].
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub time: Option<f64>,
    /// Subdivision scheme [default: the USD subdivisionScheme, else catmull-clark].
    #[arg(long, value_enum)]
    pub scheme: Option<SchemeName>,
    /// The points: a file with one `FACE U V` a line (FACE: the 0-based cage face in file
    /// order; blank lines and `#` comments are skipped), or `random:N[:SEED]` (N points, faces
    /// uniform among those that are not holes, (u,v) uniform in each face's domain; SEED 1).
    #[arg(long, value_name = "FILE|random:N[:SEED]")]
    pub uv: String,
    /// Also print the second derivatives (duu= duv= dvv=).
    #[arg(long)]
    pub second: bool,
    /// Write the lines to this file instead of standard output.
    #[arg(short, long, value_name = "OUT.txt")]
    pub output: Option<PathBuf>,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
}

/// Prints one line a point: `face=<i> u=<f> v=<f> p=<x,y,z> du=<x,y,z> dv=<x,y,z>`, and with
/// `--second` ` duu=<x,y,z> duv=<x,y,z> dvv=<x,y,z>`.
pub fn run(a: &EvaluateArgs) -> anyhow::Result<ExitCode> {
    let input = a.input.display().to_string();
    let cage = crate::load::load_cage(&a.input, a.split_nonmanifold, a.prim.as_deref(), a.time)?;
    let scheme = crate::load::cage_scheme(&a.input, &cage, a.scheme.map(Scheme::from))?;
    let eval = Evaluator::new(&cage.mesh, scheme).map_err(|e| anyhow!("{input}: {e}"))?;
    let queries = points(&eval, &a.uv)?;
    let d = if a.second {
        Derivatives::Second
    } else {
        Derivatives::First
    };
    let t0 = Instant::now();
    let mut samples = vec![Sample::default(); queries.len()];
    eval.evaluate_many(&queries, d, &mut samples)
        .map_err(|e| anyhow!("{input}: {e}"))?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let mut text = String::with_capacity(queries.len() * 160);
    for (q, s) in queries.iter().zip(&samples) {
        line(&mut text, q, s, a.second);
    }
    match &a.output {
        None => crate::out::text(&text),
        Some(path) => {
            std::fs::write(path, &text).with_context(|| format!("writing {}", path.display()))?;
            out!(
                "evaluated {} points of {input} ({}) in {ms:.1} ms -> {}",
                queries.len(),
                value_name(&SchemeName::from(scheme)),
                path.display()
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn vec3(v: DVec3) -> String {
    format!("{},{},{}", v.x, v.y, v.z)
}

/// One output line.
fn line(out: &mut String, q: &Query, s: &Sample, second: bool) {
    let _ = write!(
        out,
        "face={} u={} v={} p={} du={} dv={}",
        q.face,
        q.u,
        q.v,
        vec3(s.position),
        vec3(s.du),
        vec3(s.dv)
    );
    if second {
        let _ = write!(
            out,
            " duu={} duv={} dvv={}",
            vec3(s.duu),
            vec3(s.duv),
            vec3(s.dvv)
        );
    }
    out.push('\n');
}

/// The points of `--uv FILE|random:N[:SEED]`.
pub fn points(eval: &Evaluator<'_>, uv: &str) -> anyhow::Result<Vec<Query>> {
    match uv.strip_prefix("random:") {
        Some(spec) => random(eval, spec),
        None => read_points(eval, &PathBuf::from(uv)),
    }
}

/// `random:N[:SEED]`.
fn random(eval: &Evaluator<'_>, spec: &str) -> anyhow::Result<Vec<Query>> {
    let (n, seed) = spec.split_once(':').unwrap_or((spec, "1"));
    let n: usize = n
        .parse()
        .map_err(|_| anyhow!("--uv random:N[:SEED]: N must be a count, found '{n}'"))?;
    let seed: u64 = seed
        .parse()
        .map_err(|_| anyhow!("--uv random:N[:SEED]: SEED must be an integer, found '{seed}'"))?;
    let q = random_queries(eval, n, seed);
    if q.is_empty() && n > 0 {
        bail!("--uv random: every face of the cage is a hole");
    }
    Ok(q)
}

/// The points of a `FACE U V` file, each checked: a bad line is an error naming it.
fn read_points(eval: &Evaluator<'_>, path: &PathBuf) -> anyhow::Result<Vec<Query>> {
    let p = path.display();
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {p}"))?;
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let n = i + 1;
        let fields: Vec<&str> = line.split_whitespace().collect();
        let [face, u, v] = fields[..] else {
            bail!("{p}:{n}: expected 'FACE U V', found '{line}'");
        };
        let face: u32 = face
            .parse()
            .map_err(|_| anyhow!("{p}:{n}: FACE must be a face index (0-based), found '{face}'"))?;
        let num = |s: &str, what: &str| {
            s.parse::<f64>()
                .map_err(|_| anyhow!("{p}:{n}: {what} must be a number, found '{s}'"))
        };
        let q = Query::new(face, num(u, "U")?, num(v, "V")?);
        eval.locate(q).map_err(|e| anyhow!("{p}:{n}: {e}"))?;
        out.push(q);
    }
    Ok(out)
}
