//! `cargo xtask bench-osd [--install]`: OpenSubdiv 3.5 (Debian `libosd-dev`) beside the slates.
//!
//! Compiles `xtask/osd/bench_osd.cpp` with g++ against `/usr/include/opensubdiv` and `-losdCPU`
//! into `<target>/osd/`, runs it on the benchmark cages of `CAGES` (Catmull-Clark and Loop) at
//! their depths (OpenSubdiv cold uniform refine + limit with tangents, limit-stencil setup and
//! evaluation; see the program's header), runs `subdiv bench tessellate --scheme ..` (release
//! build, `--threads 1` and `2`) on the same cages and depths, and prints both side by side.
//! Without libosd-dev it prints how to install it and exits successfully; `--install` installs it with apt when running as root.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};

/// The cages of the benchmark, their scheme and depths: Catmull-Clark on all-quad cages, Loop on
/// all-triangle cages (the stencil locations use ptex face = cage face). A cage outside the
/// repository (`../shared/...`) is skipped when absent.
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
];
const HEADER: &str = "/usr/include/opensubdiv/far/topologyRefiner.h";
pub const INSTALL: &str = "apt-get install -y libosd-dev";

pub fn osd_present() -> bool {
    Path::new(HEADER).exists()
        && [
            "/usr/lib/x86_64-linux-gnu",
            "/usr/lib/aarch64-linux-gnu",
            "/usr/lib",
            "/usr/lib64",
            "/usr/local/lib",
        ]
        .iter()
        .any(|d| Path::new(d).join("libosdCPU.so").exists())
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

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
fn fields(text: &str, prefix: &str) -> Result<Vec<(String, f64)>> {
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

fn field(f: &[(String, f64)], key: &str) -> Result<f64> {
    f.iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| *v)
        .with_context(|| format!("no {key}= field"))
}

/// Compiles the C++ benchmark unless the binary is newer than its source.
fn build_program(root: &Path, target: &Path) -> Result<PathBuf> {
    let src = root.join("xtask/osd/bench_osd.cpp");
    let exe = target.join("osd/bench_osd");
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    if modified(&exe).is_some_and(|e| modified(&src).is_some_and(|s| e >= s)) {
        return Ok(exe);
    }
    std::fs::create_dir_all(exe.parent().expect("has a parent"))?;
    println!("bench-osd: compiling {}", src.display());
    output(
        Command::new("g++")
            .args(["-O2", "-std=c++14", "-o"])
            .arg(&exe)
            .arg(&src)
            .arg("-losdCPU"),
    )
    .context("compiling the OpenSubdiv benchmark (is g++ installed? apt-get install -y g++)")?;
    Ok(exe)
}

struct Row {
    cage: String,
    depth: u32,
    points: f64,
    /// limit points/s, patches/s with 1 and 2 threads.
    slate: [(f64, f64); 2],
    slate_bytes: f64,
    osd_cold: f64,
    osd_setup_ms: f64,
    osd_eval: f64,
    osd_evaln: f64,
}

pub fn run(root: &Path) -> Result<()> {
    let install = std::env::args().skip(2).any(|a| a == "--install");
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
            println!(
                "bench-osd: skipped: OpenSubdiv 3.5 (Debian libosd-dev) is not installed. Install it with\n    \
                 sudo {INSTALL}\nor, as root, run `cargo xtask bench-osd --install`."
            );
            return Ok(());
        }
    }
    let target = crate::target_dir();
    let osd = build_program(root, &target)?;
    crate::run({
        let mut c = crate::cargo();
        c.args(["build", "--release", "-p", "subdiv-cli"]);
        c
    })?;
    let subdiv = target
        .join("release")
        .join(format!("subdiv{}", std::env::consts::EXE_SUFFIX));

    let mut rows = Vec::new();
    for (cage, scheme, depths) in CAGES {
        let path = root.join(cage);
        if !path.exists() {
            eprintln!("bench-osd: {} is absent: skipped", path.display());
            continue;
        }
        let osd_scheme = if *scheme == "loop" { "loop" } else { "catmark" };
        for depth in depths.clone() {
            let runs = if depth >= 5 { "5" } else { "9" };
            let o = output(
                Command::new(&osd)
                    .arg(&path)
                    .arg(depth.to_string())
                    .arg(runs)
                    .arg(osd_scheme),
            )?;
            let o = fields(&o, "osd ")?;
            let mut slate = [(0.0, 0.0); 2];
            let mut slate_bytes = 0.0;
            for (i, threads) in ["1", "2"].into_iter().enumerate() {
                let s = output(
                    Command::new(&subdiv)
                        .args(["bench", "tessellate"])
                        .arg(&path)
                        .args(["--depth", &depth.to_string(), "--threads", threads])
                        .args(["--scheme", scheme]),
                )?;
                let s = fields(&s, "limit_points_per_s=")?;
                slate[i] = (
                    field(&s, "limit_points_per_s")?,
                    field(&s, "patches_per_s")?,
                );
                slate_bytes = field(&s, "slate_bytes_per_thread")?;
            }
            let name = Path::new(cage)
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
            let row = Row {
                cage: if *scheme == "loop" {
                    format!("{name} (Loop)")
                } else {
                    name
                },
                depth,
                points: field(&o, "points")?,
                slate,
                slate_bytes,
                osd_cold: field(&o, "cold_pts_per_s")?,
                osd_setup_ms: field(&o, "stencil_setup_ms")?,
                osd_eval: field(&o, "stencil_eval_pts_per_s")?,
                osd_evaln: field(&o, "stencil_evaln_pts_per_s")?,
            };
            eprintln!("bench-osd: {} depth {depth} done", row.cage);
            rows.push(row);
        }
    }

    let m = |x: f64| format!("{:.2}M", x / 1e6);
    println!(
        "\nlimit points (position + normal) per second; M = 1e6. slate: `subdiv bench tessellate` \
         (layout built once, output reused); OSD: OpenSubdiv 3.5 Far, float, single thread"
    );
    println!(
        "| cage | N | points | slate 1t | slate 2t | 2t/1t | patches/s 1t | slate B/thread | OSD cold | 1t/cold | \
         OSD stencil eval | 1t/eval | OSD eval+normals | OSD stencil setup ms |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        let s1 = r.slate[0].0;
        println!(
            "| {} | {} | {} | {} | {} | {:.2}x | {} | {} | {} | {:.1}x | {} | {:.2}x | {} | {:.1} |",
            r.cage,
            r.depth,
            r.points,
            m(s1),
            m(r.slate[1].0),
            r.slate[1].0 / s1,
            m(r.slate[0].1),
            r.slate_bytes,
            m(r.osd_cold),
            s1 / r.osd_cold,
            m(r.osd_eval),
            s1 / r.osd_eval,
            m(r.osd_evaln),
            r.osd_setup_ms
        );
    }
    Ok(())
}
