//! OpenSubdiv 3.5 (Debian `libosd-dev`), the reference of `fuzz-osd` and `bench-osd`: whether it
//! is installed, and installing it for `cargo xtask test`.

use std::path::Path;

/// A header of the installed OpenSubdiv.
const HEADER: &str = "/usr/include/opensubdiv/far/topologyRefiner.h";

/// The install command (run as root).
pub const INSTALL: &str = "apt-get install -y libosd-dev";

/// Whether OpenSubdiv's headers and `libosdCPU.so` are installed.
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

/// Makes sure OpenSubdiv 3.5 (libosd-dev) is installed, installing it as root; `Err` says
/// why it is not.
pub fn ensure_osd() -> Result<(), String> {
    let others = [
        ("Fedora", "dnf install opensubdiv-devel"),
        ("Arch", "pacman -S opensubdiv"),
    ];
    crate::vulkan::ensure_optional(
        "OpenSubdiv 3.5 (libosd-dev)",
        &["libosd-dev"],
        &others,
        &crate::vulkan::System,
        &osd_present,
    )
}
