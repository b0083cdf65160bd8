//! `cargo xtask bench-osd [--install]`: OpenSubdiv 3.5 (Debian `libosd-dev`) beside the slates.
//!
//! Compiles `xtask/osd/bench_osd.cpp` with `g++ -O3 -march=native` against
//! `/usr/include/opensubdiv` and `-losdCPU` into `<target>/osd/`. For each benchmark cage of
//! `CAGES` (Catmull-Clark and Loop) and depth it runs, interleaved over [`ROUNDS`] rounds, the
//! C++ program (OpenSubdiv cold uniform refine + limit with tangents, limit-stencil setup and
//! evaluation; see the program's header) and `subdiv bench tessellate --scheme ..` (release
//! build): one thread and two writing a frame (points, normals, indices), and one thread
//! `--points-only`. Each figure is the median over the rounds of each program's own median;
//! the point counts of both sides must be equal. It prints the table and writes everything the
//! programs printed, with the command, commit, date, host and load average, to
//! `docs/bench/bench-osd-<date>-<commit>.txt` (the raw file that docs/performance.md quotes).
//! Without libosd-dev it fails naming the install command; `--install` installs it with apt
//! when running as root.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, bail};
use xtask::osd::{INSTALL, osd_present};
use xtask::vulkan::is_root;

/// The cages of the benchmark, their scheme and depths: Catmull-Clark on all-quad cages, Loop on
/// all-triangle cages (the stencil locations use ptex face = cage face). Cages OpenSubdiv's
/// stencils cannot be compared on are left out: the teapot (a non-manifold vertex, which
/// subdiv's uniform tessellation counts twice) and cages with semi-sharp creases the adaptive
/// stencils only approximate (catmark_torus_creases0: 1e-3 off the limit). The cages in
/// `../shared/` are part of the comparison: the benchmark fails without them.
const CAGES: &[(&str, &str, std::ops::RangeInclusive<u32>)] = &[
    (
        "fixtures/reference/shapes/catmark_pawn.obj",
        "catmull-clark",
        2..=5,
    ),
    (
        "fixtures/reference/shapes/catmark_helmet.obj",
        "catmull-clark",
        2..=5,
    ),
    ("fixtures/meshes/cc_3torus.obj", "catmull-clark", 2..=5),
    ("fixtures/meshes/tri_bunny_3k.obj", "loop", 2..=5),
    ("../shared/meshes/tri_armadillo_52k.obj", "loop", 2..=3),
    ("../shared/meshes/tri_bunny_69k_holes.obj", "loop", 2..=3),
];
/// The C++ harness's compiler flags: as fast as the host allows, as the slates are (AVX2).
pub const HARNESS_FLAGS: &[&str] = &["-O3", "-march=native", "-std=c++14"];
/// Interleaved rounds per cage and depth (OpenSubdiv, then each subdiv configuration).
const ROUNDS: usize = 3;
/// Runs `cmd` and returns its stdout; fails with its stderr when it fails.
pub fn output(cmd: &mut Command) -> Result<String> {
    let shown = format!("{cmd:?}");
    let out = cmd
        .output()
        .with_context(|| format!("could not start {shown}"))?;
    if !out.status.success() {
        bail!(
            "{shown} failed with {}:\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The `key=value` fields of the last line of `text` that starts with `prefix`.
pub(crate) fn fields(text: &str, prefix: &str) -> Result<Vec<(String, f64)>> {
    let line = text
        .lines()
        .rev()
        .find(|l| l.starts_with(prefix))
        .with_context(|| format!("no line starting with {prefix:?} in:\n{text}"))?;
    Ok(line
        .split_whitespace()
        .filter_map(|kv| kv.split_once('='))
        .filter_map(|(k, v)| v.parse().ok().map(|v| (k.to_string(), v)))
        .collect())
}

pub(crate) fn field(f: &[(String, f64)], key: &str) -> Result<f64> {
    f.iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| *v)
        .with_context(|| format!("no {key}= field"))
}

/// The subdiv configurations timed beside OpenSubdiv: (label, threads, extra arguments). The
/// first also times a plain store loop over a buffer of its output's size (the write bandwidth
/// its points are held against).
const SLATE_RUNS: [(&str, &str, &[&str]); 3] = [
    ("frame 1t", "1", &["--store-bandwidth"]),
    ("frame 2t", "2", &[]),
    ("points-only 1t", "1", &["--points-only"]),
];

struct Row {
    cage: String,
    depth: u32,
    points: f64,
    /// limit points/s and patches/s of each of [`SLATE_RUNS`].
    slate: [(f64, f64); 3],
    slate_setup_ms: f64,
    slate_bytes: f64,
    /// Bytes per second of a plain store loop over the frame's output size, one thread.
    store: f64,
    osd_cold: f64,
    osd_setup_ms: f64,
    osd_eval: f64,
    osd_evaln: f64,
}

pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The load average as /proc/loadavg gives it (1, 5, 15 minutes), or `unknown`.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg").map_or_else(
        |_| "unknown".into(),
        |t| t.split_whitespace().take(3).collect::<Vec<_>>().join(" "),
    )
}

/// The header of a raw benchmark file: command, commit (with `+dirty` for local changes), date,
/// host and load average.
pub fn raw_header(root: &Path, command: &str) -> String {
    let git = |args: &[&str]| {
        Command::new("git")
            .current_dir(root)
            .args(args)
            .output()
            .ok()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .unwrap_or_default()
    };
    let dirty = !git(&["status", "--porcelain", "--untracked-files=no"]).is_empty();
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into());
    let date = Command::new("date")
        .args(["-u", "+%Y-%m-%dT%H:%M:%SZ"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    format!(
        "# command: {command}\n# commit: {}{}\n# date: {date}\n# host: {cpu}, {} threads\n# load average at start: {}\n",
        git(&["rev-parse", "--short=12", "HEAD"]),
        if dirty { "+dirty" } else { "" },
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        load_average()
    )
}

/// `bench-osd [--install]` (`args`: what follows `bench-osd`).
pub fn run(root: &Path, args: &[String]) -> Result<()> {
    let install = args.iter().any(|a| a == "--install");
    if !osd_present() {
        if install && is_root() {
            let cmd = format!("apt-get update && {INSTALL}");
            println!("bench-osd: installing OpenSubdiv: {cmd}");
            let status = Command::new("sh")
                .args(["-c", &cmd])
                .env("DEBIAN_FRONTEND", "noninteractive")
                .status()
                .context("could not run apt-get")?;
            if !status.success() || !osd_present() {
                bail!("installing libosd-dev failed ({status})");
            }
        } else {
            bail!(
                "OpenSubdiv 3.5 (Debian libosd-dev) is not installed. Install it with\n    \
                 sudo {INSTALL}\nor, as root, run `cargo xtask bench-osd --install`."
            );
        }
    }
    let target = xtask::target_dir();
    let osd = crate::fuzz_osd::build_harness_with(root, "bench_osd", HARNESS_FLAGS, "-O3-native")?;
    xtask::run({
        let mut c = xtask::cargo();
        c.args(["build", "--release", "-p", "subdiv-cli"]);
        c
    })?;
    let subdiv = target
        .join("release")
        .join(format!("subdiv{}", std::env::consts::EXE_SUFFIX));
    let mut raw = raw_header(root, "cargo xtask bench-osd");
    raw.push_str(&format!(
        "# harness: g++ {} xtask/osd/bench_osd.cpp -losdCPU\n# rounds: {ROUNDS}, interleaved: bench_osd, then subdiv {}\n",
        HARNESS_FLAGS.join(" "),
        SLATE_RUNS.map(|r| r.0).join(", ")
    ));
    let mut rows = Vec::new();
    for (cage, scheme, depths) in CAGES {
        let path = root.join(cage);
        if !path.exists() {
            bail!(
                "{} is absent (the benchmark cages are part of the comparison)",
                path.display()
            );
        }
        for depth in depths.clone() {
            let row = measure(&osd, &subdiv, cage, &path, scheme, depth, &mut raw)?;
            eprintln!("bench-osd: {} depth {depth} done", row.cage);
            rows.push(row);
        }
    }
    // The moving-cage rows (bench_animate.rs).
    let moving = crate::bench_animate::rows(root, &subdiv, &mut raw)?;
    raw.push_str(&format!("# load average at end: {}\n", load_average()));
    let table = table(&rows) + &moving;
    println!("{table}");
    raw.push_str(&table);
    let eval_table = crate::bench_eval::rows(root, &target, &subdiv, &mut raw)?;
    println!("{eval_table}");
    raw.push_str(&eval_table);
    let commit = raw
        .lines()
        .find_map(|l| l.strip_prefix("# commit: "))
        .unwrap_or("unknown")
        .to_string();
    let date = raw
        .lines()
        .find_map(|l| l.strip_prefix("# date: "))
        .and_then(|d| d.get(..10))
        .unwrap_or("unknown")
        .to_string();
    let dir = root.join("docs/bench");
    std::fs::create_dir_all(&dir)?;
    let file = dir.join(format!("bench-osd-{date}-{commit}.txt"));
    std::fs::write(&file, raw)?;
    println!("bench-osd: raw output written to {}", file.display());
    Ok(())
}

/// One cage at one depth: [`ROUNDS`] interleaved rounds of OpenSubdiv and each subdiv
/// configuration, every program's output appended to `raw`.
fn measure(
    osd: &Path,
    subdiv: &Path,
    cage: &str,
    path: &Path,
    scheme: &str,
    depth: u32,
    raw: &mut String,
) -> Result<Row> {
    let osd_scheme = if scheme == "loop" { "loop" } else { "catmark" };
    let runs = if depth >= 5 { "5" } else { "9" };
    let mut osd_rounds: Vec<Vec<(String, f64)>> = Vec::new();
    let mut slate_rounds: [Vec<Vec<(String, f64)>>; 3] = Default::default();
    for round in 0..ROUNDS {
        let args = [depth.to_string(), runs.to_string(), osd_scheme.to_string()];
        let o = output(Command::new(osd).arg(path).args(&args))?;
        raw.push_str(&format!(
            "$ bench_osd {cage} {} (round {round})\n{o}",
            args.join(" ")
        ));
        osd_rounds.push(fields(&o, "osd ")?);
        for (k, (_, threads, extra)) in SLATE_RUNS.iter().enumerate() {
            let d = depth.to_string();
            let args = [
                "bench",
                "tessellate",
                cage,
                "--depth",
                &d,
                "--threads",
                threads,
                "--scheme",
                scheme,
            ];
            let mut cmd = Command::new(subdiv);
            cmd.args(&args[..2]).arg(path).args(&args[3..]).args(*extra);
            let s = output(&mut cmd)?;
            raw.push_str(&format!(
                "$ subdiv {} {} (round {round})\n{s}",
                args.join(" "),
                extra.join(" ")
            ));
            // Both lines: the first has the counts and setup, the last the rates.
            let mut f = fields(&s, "input=")?;
            f.extend(fields(&s, "limit_points_per_s=")?);
            if extra.contains(&"--store-bandwidth") {
                f.extend(fields(&s, "store_bytes_per_s=")?);
            }
            slate_rounds[k].push(f);
        }
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
    for rounds in &slate_rounds {
        let subdiv_points = med(rounds, "limit_points")?;
        if subdiv_points != points {
            bail!(
                "{cage} depth {depth}: subdiv tessellates {subdiv_points} limit points, OpenSubdiv {points}"
            );
        }
    }
    let mut slate = [(0.0, 0.0); 3];
    for (k, rounds) in slate_rounds.iter().enumerate() {
        slate[k] = (
            med(rounds, "limit_points_per_s")?,
            med(rounds, "patches_per_s")?,
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
        slate,
        slate_setup_ms: med(&slate_rounds[0], "setup_ms")?,
        slate_bytes: med(&slate_rounds[0], "slate_bytes_per_thread")?,
        store: med(&slate_rounds[0], "store_bytes_per_s")?,
        osd_cold: med(&osd_rounds, "cold_pts_per_s")?,
        osd_setup_ms: med(&osd_rounds, "stencil_setup_ms")?,
        osd_eval: med(&osd_rounds, "stencil_eval_pts_per_s")?,
        osd_evaln: med(&osd_rounds, "stencil_evaln_pts_per_s")?,
    })
}

/// The comparison as a Markdown table.
fn table(rows: &[Row]) -> String {
    let m = |x: f64| format!("{:.2}M", x / 1e6);
    let mut t = String::from(
        "\nlimit points (position + normal) per second, M = 1e6, each the median of the rounds' \
         medians. frame: `subdiv bench tessellate` writing points, normals and indices per run; \
         points-only: `--points-only`. OSD: OpenSubdiv 3.5 Far, float, one thread; eval+n: \
         LimitStencilTable UpdateValues + UpdateDerivs + normals; setup: stencil table (OSD) and \
         layout (subdiv) from the cage. store: a plain store loop over a buffer of the frame's \
         output size, one thread; frame 24 B / store: the frame's points times 24 bytes per \
         second over it.\n",
    );
    t.push_str(
        "| cage | N | points | frame 1t | frame 2t | 2t/1t | points-only 1t | OSD eval+n | \
         frame 1t / eval+n | OSD eval | OSD cold | 1t / cold | patches/s 1t | slate B/thread | \
         layout setup ms | OSD stencil setup ms | setup / OSD setup | store GB/s | frame 24 B / store |\n",
    );
    t.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let s1 = r.slate[0].0;
        t.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.2}x | {} | {} | {:.2}x | {} | {} | {:.1}x | {} | {} | {:.3} | {:.2} | {:.3} | {:.1} | {:.3} |\n",
            r.cage,
            r.depth,
            r.points,
            m(s1),
            m(r.slate[1].0),
            r.slate[1].0 / s1,
            m(r.slate[2].0),
            m(r.osd_evaln),
            s1 / r.osd_evaln,
            m(r.osd_eval),
            m(r.osd_cold),
            s1 / r.osd_cold,
            m(r.slate[0].1),
            r.slate_bytes,
            r.slate_setup_ms,
            r.osd_setup_ms,
            r.slate_setup_ms / r.osd_setup_ms,
            r.store / 1e9,
            s1 * 24.0 / r.store,
        ));
    }
    t
}
