//! Input fuzzing, part 4: the checker. One input goes through `parse_obj`, `Mesh::from_soup`
//! (as read, after `split_nonmanifold`, the readers' default, and after
//! `split_nonmanifold_vertices`) and, for every mesh built, the depth-1
//! slate tessellation and the depth-1 uniform Catmull-Clark (and Loop, for triangle meshes)
//! tessellation of `subdiv-rules`. Every stage runs under `catch_unwind`; the properties checked:
//!
//! - no stage panics;
//! - every refusal is a typed `Err` with a non-empty message that, for a file, names a line of
//!   the file (`Empty`, `TooLarge` and `NotTriangles` have none);
//! - a mesh that is built keeps the soup's positions and faces exactly, and the repair leaves a
//!   valid mesh alone;
//! - a built mesh is tessellated (no refusal at depth 1), with finite points and normals and
//!   in-range indices, and the slate and `subdiv-rules` agree on the number of faces (Loop may
//!   refuse two triangles on the same vertices, with a typed error naming them); a mesh with a
//!   coordinate beyond `subdiv_rules::MAX_COORDINATE` is refused by both, naming the vertex.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, Once};

use subdiv_mesh::{
    CageError, CageOptions, Mesh, MeshError, ObjError, PolygonSoup, UsdError, parse_obj, read_cage,
};
use subdiv_rules::{LimitMesh, RulesError, Scheme, tessellate_uniform};

/// A property an input broke: the stage and what happened.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    /// The stage (function) at fault.
    pub stage: &'static str,
    /// The panic (message and location) or the broken property.
    pub what: String,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.stage, self.what)
    }
}

/// How far a case got.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// `parse_obj` refused it.
    ParseRefused,
    /// Validation refused it (as read and after the repair).
    MeshRefused,
    /// A mesh was built and tessellated.
    Tessellated,
}

static GUARDS: AtomicUsize = AtomicUsize::new(0);
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);
static HOOK: Once = Once::new();

/// While a [`guard`] runs, panics (on any thread) are recorded instead of printed.
fn install_hook() {
    HOOK.call_once(|| {
        let prev = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if GUARDS.load(Ordering::SeqCst) > 0 {
                let mut last = LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner());
                last.get_or_insert_with(|| info.to_string());
            } else {
                prev(info);
            }
        }));
    });
}

/// Runs `f`; a panic becomes a [`Failure`] with the panic's message and location.
pub fn guard<T>(stage: &'static str, f: impl FnOnce() -> T) -> Result<T, Failure> {
    install_hook();
    GUARDS.fetch_add(1, Ordering::SeqCst);
    let r = catch_unwind(AssertUnwindSafe(f));
    GUARDS.fetch_sub(1, Ordering::SeqCst);
    let last = LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()).take();
    r.map_err(|payload| {
        let msg = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Failure {
            stage,
            what: format!("panic: {}", last.unwrap_or(msg)),
        }
    })
}

fn fail<T>(stage: &'static str, what: String) -> Result<T, Failure> {
    Err(Failure { stage, what })
}

/// Runs one input through every stage (see the module documentation).
pub fn check(bytes: &[u8]) -> Result<Outcome, Failure> {
    let text = String::from_utf8_lossy(bytes);
    let nlines = text.lines().count() as u32;
    let soup = match guard("parse_obj", || parse_obj(&text))? {
        Ok(s) => s,
        Err(e) => {
            check_refusal("parse_obj", &e, nlines)?;
            return Ok(Outcome::ParseRefused);
        }
    };
    let plain = guard("Mesh::from_soup", || Mesh::from_soup(&soup))?;
    let mut split = soup.clone();
    let created = guard("split_nonmanifold_vertices", || {
        split.split_nonmanifold_vertices()
    })?;
    check_split(&soup, &split, &created)?;
    let mut outcome = Outcome::MeshRefused;
    match plain {
        Ok(mesh) => {
            if !created.is_empty() {
                return fail(
                    "split_nonmanifold_vertices",
                    format!("changed a valid mesh: copies {created:?}"),
                );
            }
            check_mesh("Mesh::from_soup", &soup, &mesh)?;
            tessellate_all(&mesh)?;
            outcome = Outcome::Tessellated;
        }
        Err(e) => check_refusal("Mesh::from_soup", &e, nlines)?,
    }
    // The readers' default: non-manifold cages cut into manifold pieces as OpenSubdiv refines
    // them.
    const CUT: &str = "Mesh::from_soup after split_nonmanifold";
    let mut cut = soup.clone();
    match guard("split_nonmanifold", || cut.split_nonmanifold())? {
        Ok(found) if !found.is_empty() => match guard(CUT, || Mesh::from_soup(&cut))? {
            Ok(mesh) => {
                check_mesh(CUT, &cut, &mesh)?;
                tessellate_all(&mesh)?;
                outcome = Outcome::Tessellated;
            }
            Err(e) => check_refusal(CUT, &e, nlines)?,
        },
        Ok(_) => {}
        Err(e) => check_refusal("split_nonmanifold", &e, nlines)?,
    }
    if created.is_empty() {
        return Ok(outcome);
    }
    const STAGE: &str = "Mesh::from_soup after split_nonmanifold_vertices";
    match guard(STAGE, || Mesh::from_soup(&split))? {
        Ok(mesh) => {
            check_mesh(STAGE, &split, &mesh)?;
            tessellate_all(&mesh)?;
            Ok(Outcome::Tessellated)
        }
        Err(e) => {
            check_refusal(STAGE, &e, nlines)?;
            Ok(outcome)
        }
    }
}

/// How far a USD case got: the [`Outcome`] and, for a refusal, the [`UsdError`] variant.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UsdOutcome {
    /// `ParseRefused` when the stage could not be read (`Io`, `Open`, `ReaderPanic`),
    /// `MeshRefused` for the other refusals, or `Tessellated`.
    pub outcome: Outcome,
    /// The variant of the refusal (`Open`, `Attribute`, ...); `None` when tessellated.
    pub refusal: Option<&'static str>,
    /// For a `ReaderPanic`, its message (a defect of the `openusd` parser, caught).
    pub panic: Option<String>,
}

/// Runs one USD file through `read_cage` (the product's reading path, default options) and, if
/// a cage is built, the depth-1 tessellations of [`check`]. Properties: nothing panics out of
/// `read_cage` (a panic inside `openusd` is caught at `subdiv-mesh`'s boundary and becomes
/// `UsdError::ReaderPanic`, which must point into `openusd`, not subdiv's own code); every
/// refusal is a typed `UsdError` whose message starts with the file's path; a built cage
/// tessellates to finite output.
pub fn check_usd(path: &std::path::Path) -> Result<UsdOutcome, Failure> {
    const STAGE: &str = "read_cage(usd)";
    let file = path.display().to_string();
    let read = guard(STAGE, || read_cage(path, &CageOptions::default()))?;
    let e = match read {
        Ok(cage) => {
            if cage.mesh.num_faces() == 0 {
                return fail(STAGE, "built a cage without faces".into());
            }
            tessellate_all(&cage.mesh)?;
            return Ok(UsdOutcome {
                outcome: Outcome::Tessellated,
                refusal: None,
                panic: None,
            });
        }
        Err(CageError::Usd(e)) => e,
        Err(e) => return fail(STAGE, format!("not a USD error: {e:?}")),
    };
    let msg = e.to_string();
    if !msg.starts_with(&file) || msg.trim() == file && !matches!(e, UsdError::Io { .. }) {
        return fail(STAGE, format!("error does not name the file: {msg}"));
    }
    let (outcome, refusal) = match &e {
        UsdError::Io { .. } => (Outcome::ParseRefused, "Io"),
        UsdError::Open { .. } => (Outcome::ParseRefused, "Open"),
        UsdError::ReaderPanic { .. } => (Outcome::ParseRefused, "ReaderPanic"),
        UsdError::NoMesh { .. } => (Outcome::MeshRefused, "NoMesh"),
        UsdError::NoSuchMesh { .. } => (Outcome::MeshRefused, "NoSuchMesh"),
        UsdError::Attribute { .. } => (Outcome::MeshRefused, "Attribute"),
        UsdError::Invalid { .. } => (Outcome::MeshRefused, "Invalid"),
        UsdError::Mixed { .. } => (Outcome::MeshRefused, "Mixed"),
        UsdError::Time { .. } => (Outcome::MeshRefused, "Time"),
    };
    let panic = match &e {
        UsdError::ReaderPanic { msg, .. } if !msg.contains("(at openusd") => {
            return fail(STAGE, format!("a panic outside the parser: {e}"));
        }
        UsdError::ReaderPanic { doing, msg, .. } => Some(format!("while {doing}: {msg}")),
        _ => None,
    };
    Ok(UsdOutcome {
        outcome,
        refusal: Some(refusal),
        panic,
    })
}

/// A refusal must say something and, for input from a file, name a line of it.
fn check_refusal(stage: &'static str, e: &MeshError, nlines: u32) -> Result<(), Failure> {
    let msg = e.to_string();
    if msg.trim().is_empty() {
        return fail(stage, format!("empty error message for {e:?}"));
    }
    let lineless = matches!(
        e,
        MeshError::Empty | MeshError::TooLarge { .. } | MeshError::NotTriangles { .. }
    );
    if lineless {
        return Ok(());
    }
    match e.line() {
        Some(l) if (1..=nlines).contains(&l) => {}
        other => {
            return fail(
                stage,
                format!("error names line {other:?} of {nlines}: {e:?}"),
            );
        }
    }
    if !matches!(e, MeshError::Parse { .. })
        && !["face", "vertex", "edge", "tag"]
            .iter()
            .any(|w| msg.contains(w))
    {
        return fail(stage, format!("error names no face, vertex or edge: {msg}"));
    }
    let located = ObjError::Invalid {
        path: "fuzz.obj".into(),
        err: e.clone(),
    }
    .to_string();
    if !located.starts_with(&format!("fuzz.obj:{}: ", e.line().unwrap_or(0))) {
        return fail(
            stage,
            format!("file error does not name the line: {located}"),
        );
    }
    Ok(())
}

/// The repair only appends copies, and every face corner keeps its position.
fn check_split(
    before: &PolygonSoup,
    after: &PolygonSoup,
    created: &[(u32, u32)],
) -> Result<(), Failure> {
    const STAGE: &str = "split_nonmanifold_vertices";
    let n0 = before.positions.len();
    let bits = |s: &PolygonSoup| -> Vec<[u32; 3]> {
        s.positions[..n0]
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    if after.positions.len() != n0 + created.len()
        || after.face_offsets != before.face_offsets
        || bits(after) != bits(before)
    {
        return fail(STAGE, "changed the existing vertices or faces".into());
    }
    for (&a, &b) in before.face_indices.iter().zip(&after.face_indices) {
        let pos = |s: &PolygonSoup, i: i64| {
            let p = usize::try_from(i)
                .ok()
                .and_then(|i| s.positions.get(i).copied());
            p.map(|p| p.to_array().map(f32::to_bits))
        };
        if a != b && pos(before, a) != pos(after, b) {
            return fail(
                STAGE,
                format!("corner of vertex {a} moved to {b} at another position"),
            );
        }
    }
    Ok(())
}

/// A built mesh holds exactly the soup's positions and faces, and sane sharpness.
fn check_mesh(stage: &'static str, soup: &PolygonSoup, m: &Mesh) -> Result<(), Failure> {
    if m.positions() != &soup.positions[..] || m.num_faces() != soup.num_faces() {
        return fail(
            stage,
            "mesh positions or face count differ from the file".into(),
        );
    }
    for f in m.faces() {
        let got = m.face_vertices(f).iter().map(|v| v.0 as i64);
        if !got.eq(soup.face(f.0 as usize).iter().copied()) {
            return fail(stage, format!("face {} differs from the file", f.0));
        }
    }
    let sharp_ok = |s: &f32| (0.0..=subdiv_mesh::SHARPNESS_INFINITE).contains(s);
    if !m.edge_sharpnesses().iter().all(sharp_ok) || !m.vertex_sharpnesses().iter().all(sharp_ok) {
        return fail(stage, "sharpness outside [0, 10]".into());
    }
    Ok(())
}

/// Depth-1 tessellation by the slate and by `subdiv-rules` (Catmull-Clark; Loop for triangles).
/// A cage beyond `MAX_COORDINATE` must be refused by both, naming the vertex.
fn tessellate_all(m: &Mesh) -> Result<(), Failure> {
    if let Err(e) = subdiv_rules::check_coordinates(m) {
        let slate = guard("subdiv_slate::tessellate", || {
            subdiv_slate::tessellate(m, 1)
        })?;
        let cc = guard("tessellate_uniform", || {
            tessellate_uniform(m, Scheme::CatmullClark, 1)
        })?;
        let named = |s: String| s.starts_with("vertex ") && s == e.to_string();
        return match (slate, cc) {
            (Err(a), Err(b)) if named(a.to_string()) && named(b.to_string()) => Ok(()),
            (a, b) => fail(
                "tessellate",
                format!("{e}: slate gave {:?}, subdiv-rules {:?}", a.err(), b.err()),
            ),
        };
    }
    let slate = guard("subdiv_slate::tessellate", || {
        subdiv_slate::tessellate(m, 1)
    })?
    .or_else(|e| {
        fail(
            "subdiv_slate::tessellate",
            format!("refused a valid mesh: {e}"),
        )
    })?;
    check_limit("subdiv_slate::tessellate", &slate)?;
    const CC: &str = "tessellate_uniform(CatmullClark)";
    let rules = guard(CC, || tessellate_uniform(m, Scheme::CatmullClark, 1))?
        .or_else(|e| fail(CC, format!("refused a valid mesh: {e}")))?;
    check_limit(CC, &rules)?;
    if slate.num_faces() != rules.num_faces() {
        return fail(
            "subdiv_slate::tessellate",
            format!(
                "{} faces, subdiv-rules has {}",
                slate.num_faces(),
                rules.num_faces()
            ),
        );
    }
    if m.faces().all(|f| m.face_size(f) == 3) {
        const LOOP: &str = "tessellate_uniform(Loop)";
        match guard(LOOP, || tessellate_uniform(m, Scheme::Loop, 1))? {
            Ok(lp) => check_limit(LOOP, &lp)?,
            // Two triangles on one vertex triple: Loop cannot refine them (a typed refusal).
            Err(e @ RulesError::DoubledTriangle { .. }) if e.to_string().contains("faces") => {}
            Err(e) => return fail(LOOP, format!("refused a triangle mesh: {e}")),
        }
    }
    Ok(())
}

/// Finite points and normals, well-formed face lists, indices in range.
fn check_limit(stage: &'static str, t: &LimitMesh) -> Result<(), Failure> {
    let n = t.positions().len();
    if t.normals().len() != n {
        return fail(
            stage,
            format!("{} normals for {n} points", t.normals().len()),
        );
    }
    if let Some(i) = t
        .positions()
        .iter()
        .position(|p| !p.iter().all(|x| x.is_finite()))
    {
        return fail(
            stage,
            format!("point {i} is not finite: {:?}", t.positions()[i]),
        );
    }
    if let Some(i) = t
        .normals()
        .iter()
        .position(|p| !p.iter().all(|x| x.is_finite()))
    {
        return fail(
            stage,
            format!("normal {i} is not finite: {:?}", t.normals()[i]),
        );
    }
    let offsets_ok = t.face_offsets().first().is_none_or(|&o| o == 0)
        && t.face_offsets().windows(2).all(|w| w[0] < w[1])
        && t.face_offsets()
            .last()
            .is_none_or(|&o| o as usize == t.face_indices().len());
    if !offsets_ok {
        return fail(stage, "malformed face offsets".into());
    }
    if let Some(&i) = t.face_indices().iter().find(|&&i| i as usize >= n) {
        return fail(stage, format!("face index {i} out of range ({n} points)"));
    }
    Ok(())
}
