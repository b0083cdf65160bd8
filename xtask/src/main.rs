//! `cargo xtask`: project automation (demo, tests, set-up of the Vulkan driver).
//!
//! - `cargo xtask demo`: tessellates the embedded default cage and writes `out/`.
//! - `cargo xtask test`: runs `check-architecture`, installs what the tests need (lavapipe, the
//!   validation layer, Xvfb, libosd-dev; as root) if missing, then runs every test, a short
//!   `fuzz-osd` round and the golden images. Under `CI=true` a check that cannot run fails; the
//!   last line is `xtask: N passed, F failed, K skipped (<names>)`.
//! - `cargo xtask check-architecture`: fails unless the workspace crates' dependencies on each
//!   other equal the `crate-graph` block of `docs/architecture.md`.
//! - `cargo xtask figures [doi|cc|text]`: reproduces the papers' figures and tables: data into
//!   `docs/figures/*.csv`, text generated from them into `docs/figures.md` (`doi`, `cc`: only
//!   that part; `text`: only regenerate text and plots from the CSV files).
//! - `cargo xtask golden [--bless] [--exact|--perceptual|--tolerance MEAN,P99] [SCENE...]`: golden-image regression
//!   (see `docs/golden.md`).
//! - `cargo xtask bench-osd [--install]`: OpenSubdiv 3.5 (libosd-dev) timed beside the slate
//!   tessellator (see `docs/performance.md`).
//! - `cargo xtask plot-quality [--shading] STEM LABEL=FILE...`: triangles against silhouette
//!   (or shading) error from saved `subdiv bench quality` output (see `docs/performance.md`).
//! - `cargo xtask fuzz-osd [--cages N] [--seed S] [--levels A..B] [--index I] [--fvar]`: random
//!   cages against OpenSubdiv 3.5 (see `docs/testing.md`).

mod architecture;
mod bench_osd;
mod checks;
mod figures_cc;
mod figures_cc_text;
#[cfg(test)]
mod figures_check;
mod figures_doi;
mod figures_doi_text;
mod figures_focus;
mod figures_table;
mod fuzz_osd;
mod golden;
mod plot_quality;
mod vulkan;

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};

/// The embedded default cage: OpenSubdiv's `catmark_pawn` (588 quads, semi-sharp creases).
const DEMO_CAGE: &str = include_str!("../../fixtures/reference/shapes/catmark_pawn.obj");

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// Cargo's target folder: `CARGO_TARGET_DIR` (relative to the workspace root) or `target/`.
fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root().join("target"), |t| root().join(t))
}

fn cargo() -> Command {
    let mut c = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    c.current_dir(root());
    c
}

/// Announces one xtask step on stderr (beside cargo's own progress), so a long build or test
/// run is never silent.
fn step(what: &str) {
    eprintln!("xtask: {what}...");
}

/// A progress bar of `len` steps labelled `what` on stderr, drawn only when stderr is a
/// terminal (piped output is unchanged). Print through `bar.suspend` while it runs.
fn progress(len: u64, what: &'static str) -> indicatif::ProgressBar {
    let style = indicatif::ProgressStyle::with_template(
        "{prefix} [{bar:30}] {pos}/{len} {msg} {elapsed} (eta {eta})",
    )
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
    .progress_chars("=> ");
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(len),
        indicatif::ProgressDrawTarget::stderr(),
    )
    .with_style(style)
    .with_prefix(what);
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

/// A spinner with elapsed time for one long step, like [`progress`] drawn only on a terminal.
fn spinner(what: String) -> indicatif::ProgressBar {
    let style = indicatif::ProgressStyle::with_template("{spinner} {msg} {elapsed}")
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner());
    let bar =
        indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::stderr())
            .with_style(style)
            .with_message(what);
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    bar
}

/// Builds the `subdiv` binary (`release` or the dev profile) with cargo's progress shown, and
/// returns its path.
fn build_subdiv(release: bool) -> Result<PathBuf> {
    let profile = if release { "release" } else { "debug" };
    step(&format!(
        "building subdiv ({})",
        if release { "release" } else { "dev" }
    ));
    run({
        let mut c = cargo();
        c.arg("build");
        if release {
            c.arg("--release");
        }
        c.args(["-p", "subdiv-cli"]);
        c
    })?;
    Ok(target_dir()
        .join(profile)
        .join(format!("subdiv{}", std::env::consts::EXE_SUFFIX)))
}

fn run(mut cmd: Command) -> Result<()> {
    let shown = format!("{cmd:?}");
    let status = cmd
        .status()
        .with_context(|| format!("could not start {shown}"))?;
    if !status.success() {
        bail!("{shown} failed with {status}");
    }
    Ok(())
}

/// Builds the release `subdiv` binary and runs the Catmull-Clark figures with it.
fn figures_cc_run() -> Result<()> {
    step("checking the Vulkan driver (lavapipe)");
    vulkan::ensure_driver()?;
    let exe = build_subdiv(true)?;
    // The Vulkan environment of the tests (lavapipe pinned), for the frame-rate runs.
    let mut probe = Command::new("true");
    vulkan::configure(&mut probe, &root());
    for (k, v) in probe.get_envs() {
        if let (Some(v), Some(k)) = (v, k.to_str()) {
            // SAFETY: xtask is single-threaded at this point; nothing reads the environment concurrently.
            unsafe { std::env::set_var(k, v) };
        }
    }
    figures_cc::run(&root(), &exe)
}

/// Regenerates both sections of `docs/figures.md` and the Catmull-Clark plots from the CSV
/// files in `docs/figures/` (no measuring).
fn figures_text() -> Result<()> {
    let dir = root().join("docs/figures");
    let doc = root().join("docs/figures.md");
    let doi = figures_doi_text::markdown(&figures_doi_text::DoiData::read(&dir)?)?;
    figures_cc::splice_into_doc(&doc, figures_doi_text::BEGIN, figures_doi_text::END, &doi)?;
    let data = figures_cc_text::CcData::read(&dir)?;
    figures_cc::plots(&dir, &data)?;
    let cc = figures_cc_text::markdown(&data)?;
    figures_cc::splice_into_doc(&doc, figures_cc_text::BEGIN, figures_cc_text::END, &cc)?;
    println!(
        "figures: regenerated {} from docs/figures/*.csv",
        doc.display()
    );
    Ok(())
}

fn demo() -> Result<()> {
    let out = root().join("out");
    std::fs::create_dir_all(&out)?;
    let cage = out.join("demo_cage.obj");
    std::fs::write(&cage, DEMO_CAGE)?;
    let exe = build_subdiv(true)?;
    step("running the demo");
    println!("== subdiv info (embedded cage: catmark_pawn) ==");
    run({
        let mut c = Command::new(&exe);
        c.arg("info").arg(&cage);
        c
    })?;
    println!("== subdiv tessellate --depth 4 ==");
    run({
        let mut c = Command::new(&exe);
        c.arg("tessellate")
            .arg(&cage)
            .args(["--depth", "4", "-o"])
            .arg(out.join("demo.obj"));
        c
    })?;
    step("checking the Vulkan driver (lavapipe)");
    vulkan::ensure_driver()?;
    println!("== subdiv tessellate (adaptive, view-dependent) --stats ==");
    run({
        let mut c = Command::new(&exe);
        c.arg("tessellate").arg(&cage).args([
            "--up",
            "0,0,1",
            "--eye-relative",
            "1.5,-1.7,0.9",
            "--size",
            "800x800",
            "--stats",
            "-o",
        ]);
        c.arg(out.join("demo_adaptive.obj"));
        c
    })?;
    println!("== subdiv render (adaptive, depth colours) ==");
    run({
        let mut c = Command::new(&exe);
        c.arg("render").arg(&cage).args([
            "--up",
            "0,0,1",
            "--eye-relative",
            "1.5,-1.7,0.9",
            "--shading",
            "depth",
        ]);
        c.args(["--size", "800x800", "-o"])
            .arg(out.join("demo.png"));
        vulkan::configure(&mut c, &root());
        c
    })?;
    println!(
        "demo: wrote {} and {}",
        out.join("demo.obj").display(),
        out.join("demo.png").display()
    );
    Ok(())
}

/// `cargo xtask test`: every check, tallied (see [`checks`]): under `CI=true` a check that
/// cannot run fails the run.
fn test() -> Result<()> {
    let mut checks = checks::Checks::new(checks::under_ci());
    // Cheap, and a wrong crate graph is worth knowing before the long run.
    step("checking the crate graph (docs/architecture.md)");
    checks.record("crate graph", architecture::run(&root()));
    step("checking the Vulkan driver (lavapipe), validation layer and Xvfb");
    vulkan::ensure_driver()?;
    let validation = vulkan::ensure_validation_layer();
    let xvfb = vulkan::ensure_xvfb();
    let cargo_exe = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    // Window tests (the vk viewer, `subdiv view`) need an X server: run everything under Xvfb.
    let mut c = match &xvfb {
        Ok(()) => {
            let mut c = Command::new("xvfb-run");
            c.args(["-a", "-s", "-screen 0 1280x1024x24", &cargo_exe]);
            c.env("SUBDIV_VK_REQUIRE_DISPLAY", "1");
            c
        }
        Err(_) => Command::new(&cargo_exe),
    };
    // Every test binary runs, so that one failure does not hide the others.
    c.current_dir(root())
        .args(["test", "--workspace", "--no-fail-fast"]);
    c.env("SUBDIV_VK_REQUIRE_DRIVER", "1");
    if validation.is_ok() {
        // Every Vulkan test then runs validated or fails.
        c.env(subdiv_vk::REQUIRE_VALIDATION_ENV, "1");
    }
    vulkan::configure(&mut c, &root());
    step("running cargo tests (cargo test --workspace --no-fail-fast)");
    let tests = run(c);
    let tests_ok = tests.is_ok();
    checks.record("cargo tests", tests);
    for (name, available) in [
        ("validation layer", &validation),
        ("window tests (Xvfb)", &xvfb),
    ] {
        match available {
            // These ran inside `cargo test`, required by the environment set above.
            Ok(()) if tests_ok => checks.record(name, Ok(())),
            Ok(()) => checks.record(name, Err(anyhow::anyhow!("the cargo tests failed"))),
            Err(why) => checks.unavailable(name, why),
        }
    }
    step("differential test against OpenSubdiv (short round)");
    match fuzz_osd::ensure_osd() {
        Ok(()) => checks.record("fuzz-osd round", fuzz_osd::short_round(&root())),
        Err(why) => checks.unavailable("fuzz-osd round", &why),
    }
    checks.record(
        "golden images",
        golden::run(&root(), &golden::Options::default()),
    );
    checks.finish()
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("demo") => demo(),
        Some("test") => test(),
        Some("check-architecture") => {
            step("checking the crate graph (docs/architecture.md)");
            architecture::run(&root())
        }
        Some("figures") if args.get(1).map(String::as_str) == Some("doi") => {
            step("Degree-of-Interest figures");
            figures_doi::run(&root())
        }
        Some("figures") if args.get(1).map(String::as_str) == Some("cc") => {
            step("Catmull-Clark figures");
            figures_cc_run()
        }
        Some("figures") if args.get(1).map(String::as_str) == Some("text") => {
            step("figures: text and plots from the CSV files");
            figures_text()
        }
        Some("figures") => {
            step("Degree-of-Interest figures");
            figures_doi::run(&root())?;
            step("Catmull-Clark figures");
            figures_cc_run()
        }
        Some("bench-osd") => bench_osd::run(&root()),
        Some("plot-quality") => plot_quality::run(&args[1..]),
        Some("fuzz-osd") => {
            fuzz_osd::Options::parse(&args[1..]).and_then(|o| fuzz_osd::command(&root(), &o))
        }
        Some("golden") => golden::Options::parse(&args[1..]).and_then(|o| golden::run(&root(), &o)),
        _ => {
            eprintln!(
                "usage: cargo xtask <demo|test|check-architecture|figures [doi|cc|text]|golden [--bless] [--exact|--perceptual|--tolerance MEAN,P99] [SCENE...]|bench-osd [--install]|fuzz-osd [--cages N] [--seed S] [--levels A..B] [--index I] [--fvar]|plot-quality [--shading] STEM LABEL=FILE...>"
            );
            std::process::exit(2);
        }
    }
}
