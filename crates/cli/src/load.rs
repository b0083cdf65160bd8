//! Reading input cages.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use subdiv::mesh::{Mesh, ReadOptions, TagWarning, read_obj_with_warnings};

/// `--strict` (a global flag): tag lines that are read but not applied are errors.
static STRICT: AtomicBool = AtomicBool::new(false);

/// Sets `--strict` for every cage read afterwards.
pub fn set_strict(strict: bool) {
    STRICT.store(strict, Ordering::Relaxed);
}

/// Whether `--strict` is on.
pub fn strict() -> bool {
    STRICT.load(Ordering::Relaxed)
}

/// Reads and validates a cage; errors read `FILE:LINE: what`. Tag lines that are not applied
/// are reported by [`report_tag_warnings`].
pub fn load_mesh(path: &Path, split_nonmanifold: bool) -> anyhow::Result<Mesh> {
    let (mesh, warnings) = read_obj_with_warnings(
        path,
        ReadOptions {
            split_nonmanifold_vertices: split_nonmanifold,
        },
    )?;
    log::debug!(
        "read {}: {} vertices, {} faces",
        path.display(),
        mesh.num_vertices(),
        mesh.num_faces()
    );
    report_tag_warnings(path, &warnings)?;
    Ok(mesh)
}

/// Logs `FILE:LINE: tag 't NAME' ignored (why)` as a warning (printed `warning: ...`, silenced
/// by `-q`) for each tag line that was not applied; with `--strict`, any such line is an error.
pub fn report_tag_warnings(path: &Path, warnings: &[TagWarning]) -> anyhow::Result<()> {
    let p = path.display();
    for w in warnings {
        log::warn!("{p}:{w}");
    }
    if strict() && !warnings.is_empty() {
        anyhow::bail!(
            "{p}:{}: {} tag line(s) not applied (--strict)",
            warnings[0].line,
            warnings.len()
        );
    }
    Ok(())
}
