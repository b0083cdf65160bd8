//! `cargo xtask`: project automation (demo, tests, set-up of the Vulkan driver).
//!
//! - `cargo xtask demo`: tessellates the embedded default cage and writes `out/`.
//! - `cargo xtask test`: installs what the tests need (lavapipe) if missing, then runs every test.

mod vulkan;

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, Context, Result};

/// The embedded default cage: OpenSubdiv's `catmark_pawn` (588 quads, semi-sharp creases).
const DEMO_CAGE: &str = include_str!("../../fixtures/reference/shapes/catmark_pawn.obj");

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("xtask lives in the workspace").to_path_buf()
}

fn cargo() -> Command {
    let mut c = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    c.current_dir(root());
    c
}

fn run(mut cmd: Command) -> Result<()> {
    let shown = format!("{cmd:?}");
    let status = cmd.status().with_context(|| format!("could not start {shown}"))?;
    if !status.success() {
        bail!("{shown} failed with {status}");
    }
    Ok(())
}

fn demo() -> Result<()> {
    let out = root().join("out");
    std::fs::create_dir_all(&out)?;
    let cage = out.join("demo_cage.obj");
    std::fs::write(&cage, DEMO_CAGE)?;
    run({
        let mut c = cargo();
        c.args(["build", "--release", "--quiet", "-p", "subdiv"]);
        c
    })?;
    let exe = root().join("target/release/subdiv");
    println!("== subdiv info (embedded cage: catmark_pawn) ==");
    run({
        let mut c = Command::new(&exe);
        c.arg("info").arg(&cage);
        c
    })?;
    println!("== subdiv tessellate --depth 4 ==");
    run({
        let mut c = Command::new(&exe);
        c.arg("tessellate").arg(&cage).args(["--depth", "4", "-o"]).arg(out.join("demo.obj"));
        c
    })?;
    println!("demo: wrote {}", out.join("demo.obj").display());
    Ok(())
}

fn test() -> Result<()> {
    vulkan::ensure_driver()?;
    let mut c = cargo();
    c.args(["test", "--workspace"]);
    vulkan::configure(&mut c, &root());
    run(c)
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("demo") => demo(),
        Some("test") => test(),
        _ => {
            eprintln!("usage: cargo xtask <demo|test>");
            std::process::exit(2);
        }
    }
}
