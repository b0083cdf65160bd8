//! What `xtask` and `xtask-tools` (`xtask/tools`) share: the workspace's paths, running cargo and
//! other programs, and setting up the machine (the Vulkan driver and the test dependencies). It
//! depends on no workspace crate (only `anyhow` and `serde_json`), so that `cargo xtask` builds
//! in seconds on a fresh machine.

pub mod architecture;
pub mod checks;
pub mod osd;
pub mod vulkan;

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// Cargo's target folder: `CARGO_TARGET_DIR` (relative to the workspace root) or `target/`.
pub fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root().join("target"), |t| root().join(t))
}

/// The cargo that runs xtask (`CARGO`), in the workspace root.
pub fn cargo() -> Command {
    let mut c = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    c.current_dir(root());
    c
}

/// Announces one xtask step on stderr (beside cargo's own progress), so a long build or test
/// run is never silent.
pub fn step(what: &str) {
    eprintln!("xtask: {what}...");
}

/// Runs `cmd` with its output shown; fails unless it exits successfully.
pub fn run(mut cmd: Command) -> Result<()> {
    let shown = format!("{cmd:?}");
    let status = cmd
        .status()
        .with_context(|| format!("could not start {shown}"))?;
    if !status.success() {
        bail!("{shown} failed with {status}");
    }
    Ok(())
}

/// Builds the `subdiv` binary in the cargo profile `profile` (`dev`, `release`, or `demo`: see
/// the root `Cargo.toml`) with cargo's progress shown, and returns its path.
pub fn build_subdiv(profile: &str) -> Result<PathBuf> {
    step(&format!("building subdiv ({profile})"));
    run({
        let mut c = cargo();
        c.args(["build", "--profile", profile, "-p", "subdiv-cli"]);
        c
    })?;
    // The dev profile's folder is `debug`; every other profile's is its name.
    let dir = if profile == "dev" { "debug" } else { profile };
    Ok(target_dir()
        .join(dir)
        .join(format!("subdiv{}", std::env::consts::EXE_SUFFIX)))
}
