//! `cargo xtask`: project automation (demo, tests, set-up of the Vulkan driver).
//!
//! xtask itself depends on no workspace crate (only `anyhow` and `serde_json`: see `lib.rs`), so
//! it builds in seconds; the subcommands that need the workspace libraries live in `xtask-tools`
//! (`xtask/tools`), which xtask builds and runs with `cargo run -p xtask-tools` only when one of
//! them is asked for, with the cargo features that subcommand needs: `figures` (plotters) for
//! the figures and plots, `flip` (NVIDIA FLIP, C++) for a perceptual golden comparison.
//!
//! - `cargo xtask demo`: builds the release `subdiv` binary (nothing else), tessellates the
//!   embedded default cage and writes `out/` (`out/demo.png` with its depth legend).
//! - `cargo xtask test`: runs `check-architecture`, installs what the tests need (lavapipe, the
//!   validation layer, Xvfb, libosd-dev; as root) if missing, then runs every test, a short
//!   `fuzz-osd` round and the golden images. Under `CI=true` a check that cannot run fails; the
//!   last line is `xtask: N passed, F failed, K skipped (<names>)`.
//! - `cargo xtask check-architecture`: fails unless the workspace crates' dependencies on each
//!   other equal the `crate-graph` block of `docs/architecture.md`.
//! - `cargo xtask figures [doi|cc|text] [--force]` (xtask-tools, `figures`): reproduces the
//!   papers' figures and tables: data into `docs/figures/*.csv`, text generated from them into
//!   `docs/figures.md` (`doi`, `cc`: only that part; `text`: only regenerate text and plots from
//!   the CSV files); the frame-rate figures are refused above a 1-minute load of 1.5 unless
//!   `--force`.
//! - `cargo xtask golden [--bless] [--exact|--perceptual|--tolerance MEAN,P99] [SCENE...]`
//!   (xtask-tools; `flip` when the comparison is perceptual): golden-image regression (see
//!   `docs/golden.md`).
//! - `cargo xtask bench-osd [--install]` (xtask-tools): OpenSubdiv 3.5 (libosd-dev) timed beside
//!   the slate tessellator (see `docs/performance.md`).
//! - `cargo xtask plot-quality [--shading] STEM LABEL=FILE...` (xtask-tools, `figures`):
//!   triangles against silhouette (or shading) error from saved `subdiv bench quality` output
//!   (see `docs/performance.md`).
//! - `cargo xtask fuzz-osd [--cages N] [--seed S] [--levels A..B] [--index I] [--fvar]`
//!   (xtask-tools): random cages against OpenSubdiv 3.5 (see `docs/testing.md`).

use std::process::Command;

use anyhow::{Result, bail};
use xtask::{architecture, build_subdiv, cargo, checks, osd, root, run, step, vulkan};

/// The embedded default cage: OpenSubdiv's `catmark_pawn` (588 quads, semi-sharp creases).
const DEMO_CAGE: &str = include_str!("../../fixtures/reference/shapes/catmark_pawn.obj");

/// `cargo run -p xtask-tools [--features FEATURES] -- ARGS`: builds (in the dev profile, like
/// xtask) and runs the tools binary; its exit status.
fn tools(args: &[&str], features: &[&str]) -> Result<std::process::ExitStatus> {
    let mut c = cargo();
    c.args(["run", "-p", "xtask-tools"]);
    if !features.is_empty() {
        c.arg("--features").arg(features.join(","));
    }
    c.arg("--").args(args);
    let shown = format!("{c:?}");
    c.status()
        .map_err(|e| anyhow::anyhow!("could not start {shown}: {e}"))
}

/// A tools subcommand as a check of `cargo xtask test`: fails when it exits unsuccessfully
/// (its own output, above, says why).
fn tools_check(args: &[&str], features: &[&str]) -> Result<()> {
    let status = tools(args, features)?;
    if !status.success() {
        bail!(
            "`xtask-tools {}` failed with {status} (its output above says why)",
            args.join(" ")
        );
    }
    Ok(())
}

/// Runs a subcommand of xtask-tools as the whole of this xtask run: its output is this run's,
/// and its exit status this process's.
fn forward(args: &[String], features: &[&str]) -> Result<()> {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let status = tools(&args, features)?;
    std::process::exit(status.code().unwrap_or(1));
}

/// The features `golden ARGS` needs: `flip` when it compares perceptually, that is with
/// `--perceptual`, or by default on a Mesa other than the pinned one (`Mode::Auto` in
/// `xtask/tools/src/golden.rs`); blessing compares nothing.
fn golden_features(args: &[String]) -> &'static [&'static str] {
    let has = |flag: &str| args.iter().any(|a| a == flag);
    let perceptual = has("--perceptual")
        || (!has("--exact")
            && !has("--tolerance")
            && vulkan::mesa_version().as_deref() != Some(vulkan::PINNED_MESA));
    if perceptual && !has("--bless") {
        &["flip"]
    } else {
        &[]
    }
}

fn demo() -> Result<()> {
    let out = root().join("out");
    std::fs::create_dir_all(&out)?;
    let cage = out.join("demo_cage.obj");
    std::fs::write(&cage, DEMO_CAGE)?;
    // On a fresh machine lavapipe's install (apt: network and disk) overlaps the build (CPU);
    // with the driver present this returns at once, and a failure is reported where the demo
    // first needs the driver.
    let driver = std::thread::spawn(vulkan::ensure_driver);
    let exe = match build_subdiv("demo") {
        Ok(exe) => exe,
        Err(e) => {
            // Never leave an install running behind a failed build.
            let _ = driver.join();
            return Err(e);
        }
    };
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
    driver
        .join()
        .map_err(|_| anyhow::anyhow!("the Vulkan driver check panicked"))??;
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
            "--legend",
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
            // `-noreset`: by default the X server resets whenever its last client leaves,
            // and a window test connecting during that reset (test threads start and end
            // viewers in parallel) is refused: "Failed to open connection to X server".
            c.args(["-a", "-s", "-screen 0 1280x1024x24 -noreset", &cargo_exe]);
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
        c.env(vulkan::REQUIRE_VALIDATION_ENV, "1");
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
    match osd::ensure_osd() {
        Ok(()) => checks.record("fuzz-osd round", tools_check(&["fuzz-osd-round"], &[])),
        Err(why) => checks.unavailable("fuzz-osd round", &why),
    }
    checks.record(
        "golden images",
        tools_check(&["golden"], golden_features(&[])),
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
        Some("figures" | "plot-quality") => forward(&args, &["figures"]),
        Some("golden") => forward(&args, golden_features(&args[1..])),
        Some("bench-osd" | "fuzz-osd" | "eval-refs") => forward(&args, &[]),
        _ => {
            eprintln!(
                "usage: cargo xtask <demo|test|check-architecture|figures [doi|cc|text] [--force]|golden [--bless] [--exact|--perceptual|--tolerance MEAN,P99] [SCENE...]|bench-osd [--install]|fuzz-osd [--cages N] [--seed S] [--levels A..B] [--index I] [--fvar]|eval-refs [LEVEL]|plot-quality [--shading] STEM LABEL=FILE...>"
            );
            std::process::exit(2);
        }
    }
}
