//! Finding (and on a fresh Debian/Ubuntu machine, installing) a Vulkan driver: Mesa's lavapipe.

use std::path::Path;
use std::process::Command;

use anyhow::{bail, Context, Result};

/// lavapipe's ICD manifest on Debian/Ubuntu x86_64.
pub const LAVAPIPE_ICD: &str = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
/// The Debian packages that provide the Vulkan loader and lavapipe.
pub const PACKAGES: &[&str] = &["mesa-vulkan-drivers", "libvulkan1"];

fn loader_present() -> bool {
    ["/usr/lib/x86_64-linux-gnu/libvulkan.so.1", "/usr/lib/libvulkan.so.1", "/usr/lib64/libvulkan.so.1"]
        .iter()
        .any(|p| Path::new(p).exists())
}

fn is_root() -> bool {
    Command::new("id").arg("-u").output().map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0").unwrap_or(false)
}

/// Makes sure lavapipe and the Vulkan loader are installed: installs them with apt when running
/// as root, otherwise prints the command to run and fails.
pub fn ensure_driver() -> Result<()> {
    if Path::new(LAVAPIPE_ICD).exists() && loader_present() {
        return Ok(());
    }
    let cmd = format!("apt-get update && apt-get install -y {}", PACKAGES.join(" "));
    if !is_root() {
        bail!("no Vulkan driver found (lavapipe). Install it with:\n    sudo sh -c '{cmd}'\nthen run this command again");
    }
    eprintln!("xtask: no Vulkan driver found; installing lavapipe: {cmd}");
    let status = Command::new("sh")
        .args(["-c", &cmd])
        .env("DEBIAN_FRONTEND", "noninteractive")
        .status()
        .context("could not run apt-get")?;
    if !status.success() || !Path::new(LAVAPIPE_ICD).exists() {
        bail!("installing {} failed ({status}); run as root: {cmd}", PACKAGES.join(" "));
    }
    Ok(())
}

/// Pins the Vulkan loader to lavapipe and keeps Mesa's shader cache under `target/`.
pub fn configure(cmd: &mut Command, root: &Path) {
    cmd.env("VK_DRIVER_FILES", LAVAPIPE_ICD)
        .env("VK_ICD_FILENAMES", LAVAPIPE_ICD)
        .env("MESA_SHADER_CACHE_DIR", root.join("target/mesa-shader-cache"));
}
