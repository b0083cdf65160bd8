//! `cargo xtask bench-osd`'s moving-cage rows: the per-frame update of a deforming cage, subdiv
//! against OpenSubdiv's stencil evaluation, one thread, in the same run.
//!
//! OpenSubdiv: `xtask/osd/bench_animate.cpp` (built like `bench_osd.cpp`, whose cage reader and
//! stencil locations it includes) builds the `LimitStencilTable` of every level-N vertex once,
//! then each frame sways the cage and times `UpdateValues` + `UpdateDerivs` + the normals.
//! subdiv: `subdiv bench animate CAGE --depth N --frames F --threads 1`, the same sway
//! (`subdiv_mesh::sway`), each frame timed as `StencilTessellator::update` (points and normals
//! into kept indices, from its stencil table or by the slates: the row names which). Each figure is the median over [`ROUNDS`] interleaved rounds of each
//! program's median frame; both sides must update the same number of points.

use std::path::Path;
use std::process::Command;

use anyhow::{Result, bail};

use crate::bench_osd::{HARNESS_FLAGS, field, fields, median, output};

/// The cages and depths of the rows: uniform depths 2 to 4 (the target: at least twice
/// OpenSubdiv's stencil evaluation with normals).
const CAGES: &[(&str, &str, std::ops::RangeInclusive<u32>)] = &[
    (
        "fixtures/reference/shapes/catmark_pawn.obj",
        "catmull-clark",
        2..=4,
    ),
    (
        "fixtures/reference/shapes/catmark_helmet.obj",
        "catmull-clark",
        2..=4,
    ),
    ("fixtures/meshes/cc_3torus.obj", "catmull-clark", 2..=4),
    ("fixtures/meshes/tri_bunny_3k.obj", "loop", 2..=4),
];
/// Frames per run (the sway's period).
const FRAMES: u32 = 48;
/// Interleaved rounds per cage and depth.
const ROUNDS: usize = 3;

/// One row: a cage at a depth.
struct Row {
    cage: String,
    depth: u32,
    points: f64,
    subdiv_pts: f64,
    subdiv_ms: f64,
    subdiv_setup_ms: f64,
    /// What computed subdiv's frames (`path=` of its first line).
    path: String,
    osd_pts: f64,
    osd_ms: f64,
    osd_setup_ms: f64,
}

/// Measures every cage and depth (each program's output appended to `raw`) and returns the
/// rows as a Markdown table.
pub fn rows(root: &Path, subdiv: &Path, raw: &mut String) -> Result<String> {
    let osd =
        crate::fuzz_osd::build_harness_with(root, "bench_animate", HARNESS_FLAGS, "-O3-native")?;
    raw.push_str(&format!(
        "# moving cage: g++ {} xtask/osd/bench_animate.cpp -losdCPU; {FRAMES} frames; rounds: \
         {ROUNDS}, interleaved: bench_animate, then subdiv bench animate --threads 1\n",
        HARNESS_FLAGS.join(" ")
    ));
    let mut rows = Vec::new();
    for (cage, scheme, depths) in CAGES {
        for depth in depths.clone() {
            rows.push(measure(&osd, subdiv, root, cage, scheme, depth, raw)?);
            eprintln!("bench-osd: {cage} depth {depth} (moving) done");
        }
    }
    Ok(table(&rows))
}

fn measure(
    osd: &Path,
    subdiv: &Path,
    root: &Path,
    cage: &str,
    scheme: &str,
    depth: u32,
    raw: &mut String,
) -> Result<Row> {
    let path = root.join(cage);
    let osd_scheme = if scheme == "loop" { "loop" } else { "catmark" };
    let (d, f) = (depth.to_string(), FRAMES.to_string());
    let (mut osd_rounds, mut subdiv_rounds) = (Vec::new(), Vec::new());
    let mut frames_by = String::new();
    for round in 0..ROUNDS {
        let o = output(Command::new(osd).arg(&path).args([&d, &f, osd_scheme]))?;
        raw.push_str(&format!(
            "$ bench_animate {cage} {d} {f} {osd_scheme} (round {round})\n{o}"
        ));
        osd_rounds.push(fields(&o, "osd_animate ")?);
        let args = [
            "--depth",
            &d,
            "--frames",
            &f,
            "--threads",
            "1",
            "--scheme",
            scheme,
        ];
        let s = output(
            Command::new(subdiv)
                .args(["bench", "animate"])
                .arg(&path)
                .args(args),
        )?;
        raw.push_str(&format!(
            "$ subdiv bench animate {cage} {} (round {round})\n{s}",
            args.join(" ")
        ));
        if round == 0 {
            frames_by = s
                .lines()
                .find(|l| l.starts_with("input="))
                .and_then(|l| l.split_whitespace().find_map(|kv| kv.strip_prefix("path=")))
                .unwrap_or("?")
                .to_string();
        }
        let mut fs = fields(&s, "input=")?;
        fs.extend(fields(&s, "frames=")?);
        fs.extend(fields(&s, "frame=0 ")?);
        subdiv_rounds.push(fs);
    }
    let med = |rounds: &[Vec<(String, f64)>], key: &str| -> Result<f64> {
        Ok(median(
            rounds
                .iter()
                .map(|f| field(f, key))
                .collect::<Result<Vec<_>>>()?,
        ))
    };
    let points = med(&osd_rounds, "points")?;
    let subdiv_points = med(&subdiv_rounds, "points")?;
    if subdiv_points != points {
        bail!(
            "{cage} depth {depth}: subdiv updates {subdiv_points} points a frame, OpenSubdiv {points}"
        );
    }
    let name = Path::new(cage)
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    Ok(Row {
        cage: if scheme == "loop" {
            format!("{name} (Loop)")
        } else {
            name
        },
        depth,
        points,
        subdiv_pts: med(&subdiv_rounds, "points_per_s")?,
        subdiv_ms: med(&subdiv_rounds, "update_ms_median")?,
        subdiv_setup_ms: med(&subdiv_rounds, "setup_ms")?,
        path: frames_by,
        osd_pts: med(&osd_rounds, "points_per_s")?,
        osd_ms: med(&osd_rounds, "update_ms_median")?,
        osd_setup_ms: med(&osd_rounds, "stencil_setup_ms")?,
    })
}

fn table(rows: &[Row]) -> String {
    let m = |x: f64| format!("{:.2}M", x / 1e6);
    let mut t = String::from(
        "\nmoving cage, one thread: the median frame's update of a swayed cage, in limit points \
         (position + normal) per second, M = 1e6. subdiv: `subdiv bench animate --depth N` \
         (layout kept, points and normals rewritten into kept indices: `stencils` from its limit \
         stencil table, `slates` by the slates); setup: the layout and the table; OSD: \
         LimitStencilTable built once, UpdateValues + UpdateDerivs + normals per frame\n",
    );
    t.push_str(
        "| cage | N | points | subdiv path | subdiv update | OSD stencils | subdiv / OSD | subdiv ms | \
         OSD ms | subdiv setup ms | OSD stencil setup ms |\n",
    );
    t.push_str("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        t.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {:.2}x | {:.3} | {:.3} | {:.2} | {:.1} |\n",
            r.cage,
            r.depth,
            r.points,
            r.path,
            m(r.subdiv_pts),
            m(r.osd_pts),
            r.subdiv_pts / r.osd_pts,
            r.subdiv_ms,
            r.osd_ms,
            r.subdiv_setup_ms,
            r.osd_setup_ms
        ));
    }
    t
}
