//! The harness every `subdiv` end-to-end test shares: paths, a scratch directory, the binary
//! with the tests' Vulkan environment, and runners that tell a missing driver from a failure.
//!
//! With the Khronos validation layer installed, every run has it on, and the runners that expect
//! success fail on any validation message. Without a Vulkan driver they print a note and skip,
//! unless `SUBDIV_VK_REQUIRE_DRIVER=1` (set by `cargo xtask test`).

// Each test binary uses part of the harness.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// lavapipe's ICD manifest for this machine's architecture (`lvp_icd.x86_64.json`,
/// `lvp_icd.aarch64.json`, ...), if installed.
pub fn lavapipe_icd() -> Option<PathBuf> {
    let arch = std::env::consts::ARCH;
    [
        "/usr/share/vulkan/icd.d",
        "/usr/local/share/vulkan/icd.d",
        "/etc/vulkan/icd.d",
    ]
    .iter()
    .flat_map(|d| {
        [
            format!("{d}/lvp_icd.{arch}.json"),
            format!("{d}/lvp_icd.json"),
        ]
    })
    .map(PathBuf::from)
    .find(|p| p.is_file())
}
pub const VALIDATION_LAYER: &str =
    "/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json";

pub use subdiv_test_support::root;

/// A path in this test process's scratch directory.
pub fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("subdiv-cli-tests-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// The `subdiv` binary with the Vulkan environment of the tests: lavapipe when installed and
/// nothing else was chosen, the shader cache under `target/`, validation when installed.
pub fn subdiv() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_subdiv"));
    if std::env::var_os("VK_DRIVER_FILES").is_none()
        && let Some(icd) = lavapipe_icd()
    {
        c.env("VK_DRIVER_FILES", icd);
    }
    if std::env::var_os("MESA_SHADER_CACHE_DIR").is_none() {
        c.env(
            "MESA_SHADER_CACHE_DIR",
            root().join("target/mesa-shader-cache"),
        );
    }
    // With SUBDIV_VK_REQUIRE_VALIDATION=1 (`cargo xtask test`) validation is asked for even
    // when the layer looks absent, so that the binary fails rather than runs unvalidated.
    if Path::new(VALIDATION_LAYER).exists()
        || std::env::var("SUBDIV_VK_REQUIRE_VALIDATION").as_deref() == Ok("1")
    {
        c.env("SUBDIV_VK_VALIDATION", "1");
    }
    c
}

/// The process's stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `subdiv ARGS`: exit code (-1 when killed), stdout and stderr.
pub fn run(args: &[&str]) -> (i32, String, String) {
    let o = subdiv().args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into(),
        stderr(&o),
    )
}

/// Runs `subdiv ARGS` expecting success; `None` (test skipped, note printed) when there is no
/// Vulkan driver and none is required. Fails on a validation message.
pub fn run_ok(args: &[&str]) -> Option<Output> {
    let o = subdiv().args(args).output().unwrap();
    let err = stderr(&o);
    let no_driver =
        err.contains("no Vulkan driver found") || err.contains("cannot load the Vulkan loader");
    if !o.status.success()
        && no_driver
        && std::env::var("SUBDIV_VK_REQUIRE_DRIVER").as_deref() != Ok("1")
    {
        eprintln!("skipping: {err}");
        return None;
    }
    assert!(o.status.success(), "subdiv {args:?} failed:\n{err}");
    assert!(
        !err.contains("subdiv-vk validation:"),
        "validation messages:\n{err}"
    );
    Some(o)
}

/// A failed run with exit code 1, an `error: ` line containing `want`, and no panic.
pub fn assert_clean_failure(o: &Output, want: &str) {
    let err = stderr(o);
    assert!(
        !o.status.success(),
        "expected failure, got success; stderr:\n{err}"
    );
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.starts_with("error: "), "no `error:` line:\n{err}");
    assert!(err.contains(want), "expected '{want}' in:\n{err}");
    assert!(!err.contains("panicked"), "panic:\n{err}");
}

/// Runs `subdiv ARGS` expecting a clean failure whose message contains `want`.
pub fn assert_fails(args: &[&str], want: &str) {
    let o = subdiv().args(args).output().unwrap();
    let err = stderr(&o);
    assert!(!o.status.success(), "subdiv {args:?} succeeded");
    assert!(err.contains("error"), "no error line:\n{err}");
    assert!(err.contains(want), "expected '{want}' in:\n{err}");
    assert!(!err.contains("panicked"), "panic:\n{err}");
}

/// `subdiv` in a window: on the display, or under `xvfb-run`; `None` (test skipped, note
/// printed) when there is neither and none is required.
pub fn view_command() -> Option<Command> {
    if std::env::var_os("DISPLAY").is_some() {
        return Some(subdiv());
    }
    let xvfb = std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join("xvfb-run").is_file()));
    if !xvfb {
        assert!(
            std::env::var("SUBDIV_VK_REQUIRE_DISPLAY").as_deref() != Ok("1"),
            "SUBDIV_VK_REQUIRE_DISPLAY=1 but no DISPLAY and no xvfb-run"
        );
        eprintln!("skipping: no DISPLAY and no xvfb-run (install xvfb, or run `cargo xtask test`)");
        return None;
    }
    let mut c = Command::new("xvfb-run");
    c.args([
        "-a",
        "-s",
        "-screen 0 640x480x24",
        env!("CARGO_BIN_EXE_subdiv"),
    ]);
    for (k, v) in subdiv().get_envs() {
        if let Some(v) = v {
            c.env(k, v);
        }
    }
    Some(c)
}
