//! Reading input cages (OBJ, or USD by extension).

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::anyhow;
use subdiv::mesh::{Cage, CageOptions, TagWarning, read_cage};
use subdiv::rules::Scheme;

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

/// Reads and validates a cage (the USD mesh prim `prim` (`--prim`), else every mesh of a USD
/// stage, merged), with what the file says about its subdivision; errors read `FILE:LINE: what`
/// (OBJ) or `FILE: PRIM: ATTRIBUTE: what` (USD). Tag lines that are not applied are reported
/// by [`report_tag_warnings`].
pub fn load_cage(path: &Path, split_nonmanifold: bool, prim: Option<&str>) -> anyhow::Result<Cage> {
    let cage = read_cage(
        path,
        &CageOptions {
            split_nonmanifold_vertices: split_nonmanifold,
            prim: prim.map(str::to_string),
        },
    )?;
    log::debug!(
        "read {}: {} vertices, {} faces",
        path.display(),
        cage.mesh.num_vertices(),
        cage.mesh.num_faces()
    );
    report_tag_warnings(path, &cage.warnings)?;
    Ok(cage)
}

/// The scheme to subdivide `cage` with: `--scheme` when given, else the USD
/// `subdivisionScheme`, else Catmull-Clark. USD's `bilinear` and `none` need `--scheme`.
pub fn cage_scheme(path: &Path, cage: &Cage, requested: Option<Scheme>) -> anyhow::Result<Scheme> {
    match (requested, cage.scheme) {
        (Some(s), _) => Ok(s),
        (None, None) => Ok(Scheme::CatmullClark),
        (None, Some(u)) => Scheme::from_usd(u).ok_or_else(|| {
            anyhow!(
                "{}: {}: subdivisionScheme is {}; subdiv subdivides catmullClark and loop surfaces \
                 (give --scheme to subdivide it anyway)",
                path.display(),
                cage.prims.join(" "),
                u.token()
            )
        }),
    }
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
