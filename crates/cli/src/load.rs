//! Reading input cages (OBJ, or USD by extension).

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::anyhow;
use subdiv::mesh::{Cage, CageOptions, NonManifold, TagWarning, read_cage};
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
/// stage, merged, at time code `time` (`--time`)), with what the file says about its subdivision; errors read `FILE:LINE: what`
/// (OBJ) or `FILE: PRIM: ATTRIBUTE: what` (USD). Tag lines that are not applied are reported
/// by [`report_tag_warnings`].
pub fn load_cage(
    path: &Path,
    split_nonmanifold: bool,
    prim: Option<&str>,
    time: Option<f64>,
) -> anyhow::Result<Cage> {
    let cage = read_cage(
        path,
        &CageOptions {
            split_nonmanifold_vertices: split_nonmanifold,
            prim: prim.map(str::to_string),
            time,
        },
    )?;
    log::debug!(
        "read {}: {} vertices, {} faces",
        path.display(),
        cage.mesh.num_vertices(),
        cage.mesh.num_faces()
    );
    report_tag_warnings(path, &cage.warnings)?;
    if !cage.nonmanifold.is_empty() {
        log::warn!(
            "{}: non-manifold cage, refined as OpenSubdiv does (non-manifold edges infinitely \
             sharp, non-manifold vertices corners or creases; --split-nonmanifold splits vertices \
             instead):\n{}",
            path.display(),
            nonmanifold_lines(&cage.nonmanifold).trim_end()
        );
    }
    Ok(cage)
}

/// The `subdiv info` lines (and the warning) naming what is non-manifold, 0-based vertex
/// indices as in tag lines: `non-manifold edges: N (a-b: F faces, ...)`, `non-manifold
/// vertices: N (v: F fans, ...)`, `bare vertices: N (v, ...)`; empty for a manifold cage.
pub fn nonmanifold_lines(found: &NonManifold) -> String {
    const SHOWN: usize = 12;
    let list = |items: Vec<String>| {
        let more = items.len().saturating_sub(SHOWN);
        let mut s = items.into_iter().take(SHOWN).collect::<Vec<_>>().join(", ");
        if more > 0 {
            s.push_str(&format!(", ... {more} more"));
        }
        s
    };
    let mut out = String::new();
    if !found.edges.is_empty() {
        let items = found
            .edges
            .iter()
            .map(|(a, b, n)| format!("{a}-{b}: {n} faces"));
        out += &format!(
            "non-manifold edges: {} ({})\n",
            found.edges.len(),
            list(items.collect())
        );
    }
    if !found.vertices.is_empty() {
        let items = found.vertices.iter().map(|(v, n)| format!("{v}: {n} fans"));
        out += &format!(
            "non-manifold vertices: {} ({})\n",
            found.vertices.len(),
            list(items.collect())
        );
    }
    if !found.bare.is_empty() {
        let items = found.bare.iter().map(|v| v.to_string());
        out += &format!(
            "bare vertices: {} ({})\n",
            found.bare.len(),
            list(items.collect())
        );
    }
    out
}

/// The scheme to subdivide `cage` with: `--scheme` when given, else the USD
/// `subdivisionScheme`, else Catmull-Clark. USD's `none` needs `--scheme`.
pub fn cage_scheme(path: &Path, cage: &Cage, requested: Option<Scheme>) -> anyhow::Result<Scheme> {
    match (requested, cage.scheme) {
        (Some(s), _) => Ok(s),
        (None, None) => Ok(Scheme::CatmullClark),
        (None, Some(u)) => Scheme::from_usd(u).ok_or_else(|| {
            anyhow!(
                "{}: {}: subdivisionScheme is {}, a polygon mesh rather than a subdivision surface \
                 (give --scheme to subdivide it anyway)",
                path.display(),
                cage.prims.join(" "),
                u.token()
            )
        }),
    }
}

/// Carries the primvars of `mesh` onto the diced `t` ([`subdiv::eval::tessellation_primvars`]).
pub fn dice_primvars(
    mesh: &subdiv::mesh::Mesh,
    scheme: subdiv::rules::Scheme,
    t: &mut subdiv::eval::Tessellation,
    label: &str,
) -> anyhow::Result<()> {
    subdiv::eval::tessellation_primvars(mesh, scheme, t)
        .map_err(|e| anyhow::anyhow!("{label}: {e}"))
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
