//! Finding (and on a fresh Debian/Ubuntu machine, installing) a Vulkan driver: Mesa's lavapipe.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, bail};

/// lavapipe's ICD manifest on Debian/Ubuntu x86_64.
pub const LAVAPIPE_ICD: &str = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
/// The Debian packages that provide the Vulkan loader and lavapipe.
pub const PACKAGES: &[&str] = &["mesa-vulkan-drivers", "libvulkan1"];

fn loader_present() -> bool {
    [
        "/usr/lib/x86_64-linux-gnu/libvulkan.so.1",
        "/usr/lib/libvulkan.so.1",
        "/usr/lib64/libvulkan.so.1",
    ]
    .iter()
    .any(|p| Path::new(p).exists())
}

pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// Makes sure lavapipe and the Vulkan loader are installed: installs them with apt when running
/// as root, otherwise prints the command to run and fails.
pub fn ensure_driver() -> Result<()> {
    if Path::new(LAVAPIPE_ICD).exists() && loader_present() {
        return Ok(());
    }
    let cmd = format!(
        "apt-get update && apt-get install -y {}",
        PACKAGES.join(" ")
    );
    if !is_root() {
        bail!(
            "no Vulkan driver found (lavapipe). Install it with:\n    sudo sh -c '{cmd}'\nthen run this command again"
        );
    }
    eprintln!("xtask: no Vulkan driver found; installing lavapipe: {cmd}");
    let status = Command::new("sh")
        .args(["-c", &cmd])
        .env("DEBIAN_FRONTEND", "noninteractive")
        .status()
        .context("could not run apt-get")?;
    if !status.success() || !Path::new(LAVAPIPE_ICD).exists() {
        bail!(
            "installing {} failed ({status}); run as root: {cmd}",
            PACKAGES.join(" ")
        );
    }
    Ok(())
}

/// Pins the Vulkan loader to lavapipe and keeps Mesa's shader cache under `target/`.
pub fn configure(cmd: &mut Command, root: &Path) {
    let cache = root.join("target/mesa-shader-cache");
    // Mesa does not create missing parents (e.g. no `target/` with CARGO_TARGET_DIR elsewhere).
    let _ = std::fs::create_dir_all(&cache);
    cmd.env("VK_DRIVER_FILES", LAVAPIPE_ICD)
        .env("VK_ICD_FILENAMES", LAVAPIPE_ICD)
        .env("MESA_SHADER_CACHE_DIR", cache);
}

/// The Khronos validation layer's manifest (Debian package `vulkan-validationlayers`).
pub const VALIDATION_LAYER_MANIFEST: &str =
    "/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json";

/// Xvfb and the X11 libraries winit loads at run time (for the window tests).
pub const X11_PACKAGES: &[&str] = &[
    "xvfb",
    "libx11-6",
    "libxcursor1",
    "libxrandr2",
    "libxi6",
    "libxkbcommon-x11-0",
];

/// Shared objects of [`X11_PACKAGES`] that winit opens with `dlopen`.
const X11_LIBRARIES: &[&str] = &[
    "libX11.so.6",
    "libXcursor.so.1",
    "libXrandr.so.2",
    "libXi.so.6",
    "libxkbcommon-x11.so.0",
];

fn library_present(name: &str) -> bool {
    [
        "/usr/lib/x86_64-linux-gnu",
        "/usr/lib/aarch64-linux-gnu",
        "/usr/lib",
        "/usr/lib64",
    ]
    .iter()
    .any(|d| Path::new(d).join(name).exists())
}

/// `true` when `program` is on `PATH`.
pub fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(program).is_file()))
}

/// Optional test dependencies: present already, installed now with apt (as root), or missing
/// with a note (not root, or apt failed). Returns whether they are usable.
pub fn ensure_optional(what: &str, packages: &[&str], present: &dyn Fn() -> bool) -> bool {
    if present() {
        return true;
    }
    let cmd = format!(
        "apt-get update && apt-get install -y {}",
        packages.join(" ")
    );
    if !is_root() {
        eprintln!(
            "xtask: {what} missing; those checks are skipped. Install with:\n    sudo sh -c '{cmd}'"
        );
        return false;
    }
    eprintln!("xtask: {what} missing; installing: {cmd}");
    let ok = Command::new("sh")
        .args(["-c", &cmd])
        .env("DEBIAN_FRONTEND", "noninteractive")
        .status()
        .is_ok_and(|s| s.success());
    if !ok || !present() {
        eprintln!(
            "xtask: installing {} failed; those checks are skipped",
            packages.join(" ")
        );
        return false;
    }
    true
}

/// Makes sure the Khronos validation layer is installed (so Vulkan tests run with validation);
/// returns whether it is.
pub fn ensure_validation_layer() -> bool {
    ensure_optional(
        "the Vulkan validation layer",
        &["vulkan-validationlayers"],
        &|| Path::new(VALIDATION_LAYER_MANIFEST).exists(),
    )
}

/// Makes sure `xvfb-run` and the X11 libraries winit needs are installed (for the window
/// tests); returns whether they are.
pub fn ensure_xvfb() -> bool {
    ensure_optional("Xvfb or the X11 libraries", X11_PACKAGES, &|| {
        on_path("xvfb-run") && X11_LIBRARIES.iter().all(|l| library_present(l))
    })
}
