//! The evaluation rows of `cargo xtask bench-osd`: subdiv's batched exact evaluation
//! (`subdiv bench evaluate`, release build, one thread) against OpenSubdiv 3.5's
//! `Bfr::Surface::Evaluate` (`xtask/osd/bench_eval.cpp`, one thread) on the same points of
//! the same cages, in the same run: position and first derivatives, points grouped by face,
//! each face's surface built afresh in every run on both sides. Bfr runs at its default
//! approximation levels (2 smooth, 6 sharp: what a client gets) and at level 10 (the levels
//! of the agreement tests). Two densities: 1 and 64 points per face on average (`random:N`).
//! Rounds are interleaved (Bfr default, Bfr 10, subdiv); each figure is the median over the
//! rounds of each program's own median.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result};
use subdiv::eval::{Evaluator, random_queries};
use subdiv_mesh::{CageOptions, read_cage};
use subdiv_rules::Scheme;

use crate::bench_osd::{HARNESS_FLAGS, output};

/// The cages, their schemes and the points per face.
const CAGES: &[(&str, Scheme)] = &[
    (
        "fixtures/reference/shapes/catmark_pawn.obj",
        Scheme::CatmullClark,
    ),
    (
        "fixtures/reference/shapes/catmark_helmet.obj",
        Scheme::CatmullClark,
    ),
    ("fixtures/meshes/tri_bunny_3k.obj", Scheme::Loop),
];
const DENSITIES: [usize; 2] = [1, 64];
const ROUNDS: usize = 3;
const RUNS: &str = "9";

/// The value of `key=` in the last line of `text` that has it.
fn field(text: &str, key: &str) -> Result<f64> {
    text.lines()
        .rev()
        .find_map(|l| {
            l.split_whitespace()
                .find_map(|f| f.strip_prefix(&format!("{key}=")))
        })
        .with_context(|| format!("no {key}= in:\n{text}"))?
        .parse()
        .with_context(|| format!("{key}= is not a number"))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Measures the rows, appends every program's output to `raw`, returns the markdown table.
pub fn rows(root: &Path, target: &Path, subdiv: &Path, raw: &mut String) -> Result<String> {
    let bfr = crate::fuzz_osd::build_harness_with(root, "bench_eval", HARNESS_FLAGS, "-O3-native")?;
    let dir = target.join("bench-eval");
    std::fs::create_dir_all(&dir)?;
    writeln!(
        raw,
        "# evaluation rows: g++ {} xtask/osd/bench_eval.cpp; subdiv bench evaluate --threads 1; {ROUNDS} interleaved rounds",
        HARNESS_FLAGS.join(" ")
    )?;
    let mut table = String::from(
        "| cage | points | faces | subdiv points/s (1 thread) | Bfr default levels points/s | ratio | Bfr level 10 points/s | ratio |\n|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for &(cage, scheme) in CAGES {
        let path = root.join(cage);
        let mesh = read_cage(&path, &CageOptions::default())?.mesh;
        let eval = Evaluator::new(&mesh, scheme)?;
        for density in DENSITIES {
            let queries = random_queries(&eval, density * mesh.num_faces(), 1);
            let points = dir.join(format!("points-{density}.txt"));
            let mut text = String::new();
            for q in &queries {
                writeln!(text, "{} {} {}", q.face, q.u, q.v)?;
            }
            std::fs::write(&points, text)?;
            let scheme_arg = if scheme == Scheme::Loop {
                "loop"
            } else {
                "catmark"
            };
            let scheme_cli = if scheme == Scheme::Loop {
                "loop"
            } else {
                "catmull-clark"
            };
            let (mut ours, mut dflt, mut deep) = (Vec::new(), Vec::new(), Vec::new());
            let mut faces = 0.0;
            for _ in 0..ROUNDS {
                for (level, into) in [(None, &mut dflt), (Some("10"), &mut deep)] {
                    let mut cmd = Command::new(&bfr);
                    cmd.arg(&path).arg(scheme_arg).arg(&points).arg(RUNS);
                    cmd.args(level);
                    let out = output(&mut cmd)?;
                    raw.push_str(&out);
                    into.push(field(&out, "points_per_s")?);
                    faces = field(&out, "faces")?;
                }
                let out = output(
                    Command::new(subdiv)
                        .args(["bench", "evaluate"])
                        .arg(&path)
                        .args([
                            "--scheme",
                            scheme_cli,
                            "--threads",
                            "1",
                            "--runs",
                            RUNS,
                            "--uv",
                        ])
                        .arg(&points),
                )?;
                raw.push_str(&out);
                ours.push(field(&out, "points_per_s")?);
            }
            let (o, d, l) = (median(ours), median(dflt), median(deep));
            writeln!(
                table,
                "| {} | {} | {faces} | {o:.0} | {d:.0} | {:.2} | {l:.0} | {:.2} |",
                Path::new(cage)
                    .file_name()
                    .unwrap_or_default()
                    .to_string_lossy(),
                queries.len(),
                o / d,
                o / l
            )?;
            eprintln!("bench-osd: evaluation {cage} {density} points/face done");
        }
    }
    Ok(table)
}
