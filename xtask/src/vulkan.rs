//! Finding (and on a fresh Debian/Ubuntu machine, installing) a Vulkan driver: Mesa's lavapipe.
//!
//! Paths follow the machine's architecture (`lvp_icd.x86_64.json`, `lvp_icd.aarch64.json`,
//! `/usr/lib/<arch>-linux-gnu/`); on systems without apt, xtask names the packages to install.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};

/// Folders that hold Vulkan ICD manifests (the loader's system search path).
const ICD_DIRS: &[&str] = &[
    "/usr/share/vulkan/icd.d",
    "/usr/local/share/vulkan/icd.d",
    "/etc/vulkan/icd.d",
];
/// The Debian packages that provide the Vulkan loader and lavapipe.
pub const PACKAGES: &[&str] = &["mesa-vulkan-drivers", "libvulkan1"];

/// Package names on other distributions: (distribution, install command).
const OTHER_DISTROS: &[(&str, &str)] = &[
    (
        "Fedora/RHEL",
        "dnf install mesa-vulkan-drivers vulkan-loader",
    ),
    ("Arch Linux", "pacman -S vulkan-swrast vulkan-icd-loader"),
    ("Alpine", "apk add mesa-vulkan-swrast vulkan-loader"),
];

/// The lavapipe ICD manifest for `arch` (`std::env::consts::ARCH`) among the files of `dirs`:
/// `lvp_icd.<arch>.json` first, then an unsuffixed `lvp_icd.json`, then any `lvp_icd*.json` that
/// names the architecture. Manifests of other architectures (multiarch `i686`) are never chosen.
pub fn find_lavapipe_icd<P: AsRef<Path>>(dirs: &[P], arch: &str) -> Option<PathBuf> {
    let exact = [format!("lvp_icd.{arch}.json"), "lvp_icd.json".to_string()];
    for name in &exact {
        for d in dirs {
            let p = d.as_ref().join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    for d in dirs {
        let Ok(entries) = std::fs::read_dir(d) else {
            continue;
        };
        let mut found: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
                    n.starts_with("lvp_icd") && n.ends_with(".json") && n.contains(arch)
                })
            })
            .collect();
        found.sort();
        if let Some(p) = found.into_iter().next() {
            return Some(p);
        }
    }
    None
}

/// lavapipe's ICD manifest on this machine, if installed.
pub fn lavapipe_icd() -> Option<PathBuf> {
    find_lavapipe_icd(ICD_DIRS, std::env::consts::ARCH)
}

/// Library folders to look in: the Debian multiarch folder of this architecture
/// (`/usr/lib/x86_64-linux-gnu`, `/usr/lib/aarch64-linux-gnu`), then `/usr/lib64`, `/usr/lib`.
fn library_dirs() -> Vec<PathBuf> {
    vec![
        PathBuf::from(format!("/usr/lib/{}-linux-gnu", std::env::consts::ARCH)),
        PathBuf::from("/usr/lib64"),
        PathBuf::from("/usr/lib"),
    ]
}

fn library_present(name: &str) -> bool {
    library_dirs().iter().any(|d| d.join(name).exists())
}

fn loader_present() -> bool {
    library_present("libvulkan.so.1")
}

pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// `true` when apt can install packages here (Debian, Ubuntu and derivatives).
fn has_apt() -> bool {
    on_path("apt-get")
}

/// What to install on a system without apt: the Debian names and the other distributions'
/// equivalents of `what` (pairs of distribution and install command).
fn non_debian_message(what: &str, debian: &[&str], others: &[(&str, &str)]) -> String {
    let mut m = format!(
        "{what} missing, and this system has no apt-get. Install with your package manager:\n    \
         Debian/Ubuntu: sudo apt-get install {}",
        debian.join(" ")
    );
    for (distro, cmd) in others {
        m.push_str(&format!("\n    {distro}: sudo {cmd}"));
    }
    m
}

/// Makes sure lavapipe and the Vulkan loader are installed: installs them with apt when running
/// as root, otherwise prints the command to run and fails.
pub fn ensure_driver() -> Result<()> {
    if lavapipe_icd().is_some() && loader_present() {
        return Ok(());
    }
    if !has_apt() {
        bail!(
            "{}\nthen run this command again",
            non_debian_message(
                "the Vulkan loader or Mesa's lavapipe driver (lvp_icd.*.json)",
                PACKAGES,
                OTHER_DISTROS
            )
        );
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
    if !status.success() || lavapipe_icd().is_none() {
        bail!(
            "installing {} failed ({status}); run as root: {cmd}",
            PACKAGES.join(" ")
        );
    }
    Ok(())
}

/// The Mesa release whose lavapipe renders the committed goldens byte for byte (Debian 12).
pub const PINNED_MESA: &str = "22.3.6";

/// The upstream version of the installed lavapipe package (`22.3.6` for Debian's
/// `22.3.6-1+deb12u2`), asked of dpkg, rpm or pacman; `None` when none of them knows it.
pub fn mesa_version() -> Option<String> {
    let ask = |program: &str, args: &[&str]| -> Option<String> {
        let out = Command::new(program).args(args).output().ok()?;
        let text = String::from_utf8_lossy(&out.stdout).trim().to_string();
        (out.status.success() && !text.is_empty()).then_some(text)
    };
    let full = ask(
        "dpkg-query",
        &["-W", "-f", "${Version}", "mesa-vulkan-drivers"],
    )
    .or_else(|| ask("rpm", &["-q", "--qf", "%{VERSION}", "mesa-vulkan-drivers"]))
    .or_else(|| {
        ask("pacman", &["-Q", "vulkan-swrast"])
            .and_then(|t| t.split_whitespace().nth(1).map(str::to_string))
    })?;
    Some(upstream_version(&full).to_string())
}

/// `22.3.6` from a package version such as `1:22.3.6-1+deb12u2` (no epoch, no revision).
pub fn upstream_version(package_version: &str) -> &str {
    let v = package_version
        .split_once(':')
        .map_or(package_version, |(_, v)| v);
    v.split('-').next().unwrap_or(v)
}

/// Pins the Vulkan loader to lavapipe and keeps Mesa's shader cache under `target/`.
pub fn configure(cmd: &mut Command, root: &Path) {
    let cache = root.join("target/mesa-shader-cache");
    // Mesa does not create missing parents (e.g. no `target/` with CARGO_TARGET_DIR elsewhere).
    let _ = std::fs::create_dir_all(&cache);
    if let Some(icd) = lavapipe_icd() {
        cmd.env("VK_DRIVER_FILES", &icd)
            .env("VK_ICD_FILENAMES", &icd);
    }
    cmd.env("MESA_SHADER_CACHE_DIR", cache);
}

/// The variable that makes every Vulkan context of the tests demand the validation layer: the
/// value of `subdiv_vk::REQUIRE_VALIDATION_ENV` (xtask depends on no workspace crate; a test of
/// `xtask-tools` holds the two equal).
pub const REQUIRE_VALIDATION_ENV: &str = "SUBDIV_VK_REQUIRE_VALIDATION";

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

/// `true` when `program` is on `PATH`.
pub fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(program).is_file()))
}

/// What installing a test dependency needs of the machine: apt, root and the install itself
/// (a trait, so that the tests can stand in for a machine without them).
pub trait Installer {
    fn has_apt(&self) -> bool;
    fn is_root(&self) -> bool;
    /// Runs the shell command `cmd`; whether it succeeded.
    fn run(&self, cmd: &str) -> bool;
}

/// This machine.
pub struct System;

impl Installer for System {
    fn has_apt(&self) -> bool {
        has_apt()
    }
    fn is_root(&self) -> bool {
        is_root()
    }
    fn run(&self, cmd: &str) -> bool {
        Command::new("sh")
            .args(["-c", cmd])
            .env("DEBIAN_FRONTEND", "noninteractive")
            .status()
            .is_ok_and(|s| s.success())
    }
}

/// A test dependency: present already, or installed now with apt (as root). `Err` says why it
/// is unusable (no apt, not root, the install failed) and how to install it; the caller decides
/// whether that skips its checks or fails the run (see [`crate::checks`]).
pub fn ensure_optional(
    what: &str,
    packages: &[&str],
    others: &[(&str, &str)],
    system: &dyn Installer,
    present: &dyn Fn() -> bool,
) -> Result<(), String> {
    if present() {
        return Ok(());
    }
    if !system.has_apt() {
        return Err(non_debian_message(what, packages, others));
    }
    let cmd = format!(
        "apt-get update && apt-get install -y {}",
        packages.join(" ")
    );
    if !system.is_root() {
        return Err(format!(
            "{what} missing and not root. Install with:\n    sudo sh -c '{cmd}'"
        ));
    }
    eprintln!("xtask: {what} missing; installing: {cmd}");
    if !system.run(&cmd) || !present() {
        return Err(format!("{what} missing: installing with `{cmd}` failed"));
    }
    Ok(())
}

/// Makes sure the Khronos validation layer is installed (so Vulkan tests run with validation).
pub fn ensure_validation_layer() -> Result<(), String> {
    ensure_optional(
        "the Vulkan validation layer",
        &["vulkan-validationlayers"],
        &[
            ("Fedora/RHEL", "dnf install vulkan-validation-layers"),
            ("Arch Linux", "pacman -S vulkan-validation-layers"),
        ],
        &System,
        &|| Path::new(VALIDATION_LAYER_MANIFEST).exists(),
    )
}

/// Makes sure `xvfb-run` and the X11 libraries winit needs are installed (for the window
/// tests).
pub fn ensure_xvfb() -> Result<(), String> {
    let others = [
        (
            "Fedora/RHEL",
            "dnf install xorg-x11-server-Xvfb libX11 libXcursor libXrandr libXi libxkbcommon-x11",
        ),
        (
            "Arch Linux",
            "pacman -S xorg-server-xvfb libx11 libxcursor libxrandr libxi libxkbcommon-x11",
        ),
    ];
    ensure_optional(
        "Xvfb or the X11 libraries",
        X11_PACKAGES,
        &others,
        &System,
        &|| on_path("xvfb-run") && X11_LIBRARIES.iter().all(|l| library_present(l)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lavapipe_icd_follows_the_architecture() {
        let d = std::env::temp_dir().join(format!("xtask-icd-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let touch = |n: &str| std::fs::write(d.join(n), "{}").unwrap();
        // Multiarch: only another architecture's manifest is never chosen.
        touch("lvp_icd.i686.json");
        touch("radeon_icd.aarch64.json");
        assert_eq!(find_lavapipe_icd(&[&d], "aarch64"), None);
        assert_eq!(find_lavapipe_icd(&[&d], "x86_64"), None);
        touch("lvp_icd.aarch64.json");
        touch("lvp_icd.x86_64.json");
        assert_eq!(
            find_lavapipe_icd(&[&d], "aarch64"),
            Some(d.join("lvp_icd.aarch64.json"))
        );
        assert_eq!(
            find_lavapipe_icd(&[&d], "x86_64"),
            Some(d.join("lvp_icd.x86_64.json"))
        );
        // Other spellings that name the architecture (e.g. a versioned manifest).
        std::fs::remove_file(d.join("lvp_icd.aarch64.json")).unwrap();
        touch("lvp_icd.aarch64.1.json");
        assert_eq!(
            find_lavapipe_icd(&[&d], "aarch64"),
            Some(d.join("lvp_icd.aarch64.1.json"))
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn upstream_versions() {
        assert_eq!(upstream_version("22.3.6-1+deb12u2"), "22.3.6");
        assert_eq!(upstream_version("1:24.2.8-1ubuntu1"), "24.2.8");
        assert_eq!(upstream_version("24.1.0"), "24.1.0");
    }

    #[test]
    fn non_debian_message_names_the_packages() {
        let m = non_debian_message("lavapipe", PACKAGES, OTHER_DISTROS);
        assert!(
            m.contains("apt-get install mesa-vulkan-drivers libvulkan1"),
            "{m}"
        );
        assert!(
            m.contains("dnf install mesa-vulkan-drivers vulkan-loader"),
            "{m}"
        );
        assert!(m.contains("pacman -S vulkan-swrast"), "{m}");
    }
}
