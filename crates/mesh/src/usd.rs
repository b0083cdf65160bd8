//! USD input: the `UsdGeomMesh` prims of a `.usda`, `.usdc` or `.usdz` stage, read with the
//! pure-Rust `openusd` crate (composition included: references, payloads, variants, ...).
//!
//! A mesh prim maps to the same [`PolygonSoup`] and tags an OBJ cage with OpenSubdiv's `t` lines
//! gives (see [`crate::read_obj`]):
//!
//! | USD attribute | subdiv |
//! | --- | --- |
//! | `points`, `faceVertexCounts`, `faceVertexIndices` | positions and faces, in the file's order |
//! | `creaseIndices`, `creaseLengths`, `creaseSharpnesses` | one [`CreaseTag`] per crease edge (one sharpness per crease or per edge) |
//! | `cornerIndices`, `cornerSharpnesses` | [`CornerTag`]s |
//! | `holeIndices` | [`HoleTag`]s |
//! | `interpolateBoundary` (default `edgeAndCorner`) | [`BoundaryInterpolation`] |
//! | `triangleSubdivisionRule` (`catmullClark`, `smooth`) | [`TriangleSubdivision`] |
//! | `subdivisionScheme` (default `catmullClark`) | [`UsdScheme`], for the caller to choose a scheme |
//! | `faceVaryingLinearInterpolation` (default `cornersPlus1`) | [`FaceVaryingLinear`], kept for face-varying data (not read yet) |
//! | `orientation` `leftHanded` | every face's winding reversed (vertex 0 first), so faces are counter-clockwise |
//! | the prim's `xformOp`s and its ancestors' | applied to the points (local-to-world, in `f64`) |
//!
//! A transform that mirrors (negative determinant) also reverses the winding, so faces stay
//! counter-clockwise seen from outside in world space. Every attribute is read at
//! [`UsdReadOptions::time`] (time samples interpolated as USD does), or without one at its
//! default value, else its earliest time sample; [`UsdStageReader`] reads a stage at many
//! times. USD's creasing is uniform (OpenSubdiv's `creasemethod` is not a USD attribute):
//! meshes from USD use [`CreaseMethod::Uniform`](crate::CreaseMethod::Uniform).
//!
//! A stage with several meshes: [`UsdReadOptions::prim`] picks one by path; without it every
//! active mesh prim is read and merged into one cage, each prim a face group named by its path
//! (vertices, faces and tags renumbered in traversal order). Merged prims must agree on the
//! scheme and the options, which are per mesh in subdiv.
//!
//! Every problem is a [`UsdError`] naming the file, the prim and the attribute; topology errors
//! are the [`MeshError`]s of [`Mesh::from_soup`] for that prim alone (its own face and vertex
//! numbers). A panic inside the `openusd` reader (a defect of the reader, on malformed input) is
//! caught and returned as [`UsdError::ReaderPanic`].

mod catch;
mod prim;
mod time;

use std::path::Path;

use openusd::sdf;
use openusd::usd::{PrimPredicate, Stage};
pub use time::{StageTime, UsdStageReader};

use crate::error::{MeshError, UsdError};
use crate::mesh::Mesh;
use crate::soup::{CornerTag, CreaseTag, HoleTag, PolygonSoup};

/// The `subdivisionScheme` of a USD mesh.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum UsdScheme {
    /// `catmullClark` (the USD default).
    #[default]
    CatmullClark,
    /// `loop` (triangle meshes).
    Loop,
    /// `bilinear`: OpenSubdiv's bilinear scheme.
    Bilinear,
    /// `none`: a polygon mesh, not a subdivision surface.
    None,
}

impl UsdScheme {
    /// The USD token (`catmullClark`, `loop`, `bilinear`, `none`).
    pub fn token(self) -> &'static str {
        match self {
            UsdScheme::CatmullClark => "catmullClark",
            UsdScheme::Loop => "loop",
            UsdScheme::Bilinear => "bilinear",
            UsdScheme::None => "none",
        }
    }
}

/// USD's `faceVaryingLinearInterpolation` (OpenSubdiv's `FVarLinearInterpolation`): how
/// face-varying data such as UVs is interpolated. Read and checked, kept for face-varying data.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum FaceVaryingLinear {
    /// `none`: smooth everywhere.
    None,
    /// `cornersOnly`: sharp corners.
    CornersOnly,
    /// `cornersPlus1` (the USD default): sharp corners and junctions.
    #[default]
    CornersPlus1,
    /// `cornersPlus2`: as `cornersPlus1`, plus darts and concave corners.
    CornersPlus2,
    /// `boundaries`: linear along boundaries.
    Boundaries,
    /// `all`: linear everywhere.
    All,
}

impl FaceVaryingLinear {
    /// The USD token (`none`, `cornersOnly`, ...).
    pub fn token(self) -> &'static str {
        match self {
            FaceVaryingLinear::None => "none",
            FaceVaryingLinear::CornersOnly => "cornersOnly",
            FaceVaryingLinear::CornersPlus1 => "cornersPlus1",
            FaceVaryingLinear::CornersPlus2 => "cornersPlus2",
            FaceVaryingLinear::Boundaries => "boundaries",
            FaceVaryingLinear::All => "all",
        }
    }
}

/// Options of [`read_usd`].
#[derive(Clone, Debug, Default)]
pub struct UsdReadOptions {
    /// The path of the mesh prim to read (`/World/Body`); `None` reads and merges every mesh.
    pub prim: Option<String>,
    /// Repair non-manifold vertices (see [`PolygonSoup::split_nonmanifold_vertices`]).
    pub split_nonmanifold_vertices: bool,
    /// The time code to read at (see [`UsdStageReader`]); `None` reads default values, else
    /// the earliest time samples.
    pub time: Option<f64>,
}

/// The mesh prims of a stage as one cage soup, in world space.
#[derive(Clone, Debug, Default)]
pub struct UsdCage {
    /// Positions (world space), faces and tags; each prim is a face group named by its path.
    pub soup: PolygonSoup,
    /// The prims' `subdivisionScheme`.
    pub scheme: UsdScheme,
    /// The prims' `faceVaryingLinearInterpolation`.
    pub face_varying: FaceVaryingLinear,
    /// The paths of the prims read, in order.
    pub prims: Vec<String>,
}

/// A validated cage read from USD, with what the file says about its subdivision.
#[derive(Clone, Debug)]
pub struct UsdMesh {
    /// The cage.
    pub mesh: Mesh,
    /// The prims' `subdivisionScheme`.
    pub scheme: UsdScheme,
    /// The prims' `faceVaryingLinearInterpolation`.
    pub face_varying: FaceVaryingLinear,
    /// The paths of the prims read, in order.
    pub prims: Vec<String>,
    /// What was non-manifold (see [`crate::PolygonSoup::split_nonmanifold`]).
    pub nonmanifold: crate::NonManifold,
}

/// Whether `path` names a USD file (`.usd`, `.usda`, `.usdc`, `.usdz`, any case).
pub fn is_usd_path(path: impl AsRef<Path>) -> bool {
    path.as_ref()
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| {
            ["usd", "usda", "usdc", "usdz"]
                .iter()
                .any(|x| e.eq_ignore_ascii_case(x))
        })
}

/// Reads the mesh prims of a USD stage and builds a validated cage (see the module docs), at
/// [`UsdReadOptions::time`].
///
/// ```no_run
/// use subdiv_mesh::{UsdReadOptions, read_usd};
/// let cage = read_usd("cage.usda", &UsdReadOptions::default()).unwrap();
/// println!("{} faces from {:?}", cage.mesh.num_faces(), cage.prims);
/// ```
pub fn read_usd(path: impl AsRef<Path>, opts: &UsdReadOptions) -> Result<UsdMesh, UsdError> {
    UsdStageReader::open(path, opts)?.read_at(opts.time)
}

/// Builds the validated cage of a soup read from `file`: non-manifold parts cut (or split with
/// `split_nonmanifold_vertices`), then [`Mesh::from_soup`].
fn build_cage(
    file: &str,
    mut cage: UsdCage,
    split_nonmanifold_vertices: bool,
) -> Result<UsdMesh, UsdError> {
    let invalid = |err, prims: &[String]| UsdError::Invalid {
        path: file.to_string(),
        prim: prims.join(" "),
        attr: attribute_of(&err),
        err,
    };
    let found = cage.soup.prepare_nonmanifold(split_nonmanifold_vertices);
    let nonmanifold = found.map_err(|e| invalid(e, &cage.prims))?;
    let mesh = Mesh::from_soup(&cage.soup).map_err(|e| invalid(e, &cage.prims))?;
    Ok(UsdMesh {
        mesh,
        scheme: cage.scheme,
        face_varying: cage.face_varying,
        prims: cage.prims,
        nonmanifold,
    })
}

/// Reads the mesh prims of a USD stage into one soup at time code `time` (`None`: default
/// values, else the earliest time samples), without validating the merged topology (each
/// prim is validated on its own, so errors name the prim's own faces and vertices).
///
/// A panic inside the `openusd` reader is caught here and returned as
/// [`UsdError::ReaderPanic`].
pub fn read_usd_soup(
    path: impl AsRef<Path>,
    prim: Option<&str>,
    time: Option<f64>,
) -> Result<UsdCage, UsdError> {
    let opts = UsdReadOptions {
        prim: prim.map(str::to_string),
        ..UsdReadOptions::default()
    };
    UsdStageReader::open(path, &opts)?.read_soup_at(time)
}

/// Validates one prim's soup on its own, as the reader built it (non-manifold prims cut as
/// OpenSubdiv refines them), so that errors name the prim's own faces and vertices.
fn check_prim(file: &str, prim: &str, soup: &PolygonSoup) -> Result<(), UsdError> {
    let mut alone = soup.clone();
    let built = alone
        .split_nonmanifold()
        .and_then(|_| Mesh::from_soup(&alone));
    built.map(|_| ()).map_err(|err| UsdError::Invalid {
        path: file.to_string(),
        prim: prim.to_string(),
        attr: attribute_of(&err),
        err,
    })
}

/// The paths of the active, defined mesh prims, in traversal order.
fn mesh_prims(stage: &Stage, file: &str) -> Result<Vec<String>, UsdError> {
    let mut paths = Vec::new();
    stage
        .traverse(PrimPredicate::DEFAULT, |p| paths.push(p.clone()))
        .map_err(|e| UsdError::Open {
            path: file.to_string(),
            msg: format!("{e:#}"),
        })?;
    let mut meshes = Vec::new();
    for p in paths {
        let t = stage.prim(p.clone()).type_name().ok().flatten();
        if t.as_deref() == Some("Mesh") {
            meshes.push(p.as_str().to_string());
        }
    }
    Ok(meshes)
}

/// `--prim` names no mesh: say whether the prim exists (and what it is) and list the meshes.
fn prim_not_found(stage: &Stage, file: &str, p: &str, meshes: &[String]) -> UsdError {
    let kind = sdf::path(p)
        .ok()
        .and_then(|sp| stage.prim(sp).type_name().ok().flatten())
        .map(|t| t.as_str().to_string());
    UsdError::NoSuchMesh {
        path: file.to_string(),
        prim: p.to_string(),
        found: kind.map_or_else(
            || "no such prim".to_string(),
            |t| format!("a {t} prim, not a Mesh"),
        ),
        meshes: if meshes.is_empty() {
            "none".to_string()
        } else {
            meshes.join(", ")
        },
    }
}

/// Appends one prim's soup to the cage: indices offset, the prim a face group of its own.
fn merge(cage: &mut UsdCage, one: prim::PrimMesh, file: &str) -> Result<(), UsdError> {
    let prim = one.path;
    if let Some(first) = cage.prims.first() {
        let disagree = |attr: &'static str, a: String, b: String| UsdError::Mixed {
            path: file.to_string(),
            attr,
            a: format!("{first} ({a})"),
            b: format!("{prim} ({b})"),
        };
        if cage.scheme != one.scheme {
            let (a, b) = (cage.scheme.token().into(), one.scheme.token().into());
            return Err(disagree("subdivisionScheme", a, b));
        }
        let (a, b) = (cage.soup.options, one.soup.options);
        if a.boundary != b.boundary {
            return Err(disagree(
                "interpolateBoundary",
                format!("{:?}", a.boundary),
                format!("{:?}", b.boundary),
            ));
        }
        if a.triangles != b.triangles {
            return Err(disagree(
                "triangleSubdivisionRule",
                format!("{:?}", a.triangles),
                format!("{:?}", b.triangles),
            ));
        }
        if cage.soup.uv_indices.is_empty() != one.soup.uv_indices.is_empty() {
            let has = |s: &PolygonSoup| {
                if s.uv_indices.is_empty() {
                    "no primvars:st".to_string()
                } else {
                    "primvars:st".to_string()
                }
            };
            return Err(disagree("primvars:st", has(&cage.soup), has(&one.soup)));
        }
        if cage.face_varying != one.face_varying {
            let (a, b) = (cage.face_varying.token(), one.face_varying.token());
            return Err(disagree(
                "faceVaryingLinearInterpolation",
                a.into(),
                b.into(),
            ));
        }
        merge_primvars(&mut cage.soup, &one.soup, file, first, &prim)?;
    } else {
        cage.scheme = one.scheme;
        cage.face_varying = one.face_varying;
        cage.soup.options = one.soup.options;
        cage.soup.primvars = one.soup.primvars.clone();
    }
    let out = &mut cage.soup;
    let (bv, bf) = (out.positions.len() as i64, out.num_faces() as i64);
    let group = out.groups.len() as u32;
    out.groups.push(prim.clone());
    out.positions.extend_from_slice(&one.soup.positions);
    let bt = out.uvs.len() as i64;
    out.uvs.extend_from_slice(&one.soup.uvs);
    out.uv_indices.extend(
        one.soup
            .uv_indices
            .iter()
            .map(|&t| if t < 0 { t } else { t + bt }),
    );
    for f in 0..one.soup.num_faces() {
        out.push_face(one.soup.face(f).iter().map(|&i| i + bv));
        out.face_groups.push(group);
    }
    let s = one.soup;
    out.creases.extend(s.creases.iter().map(|t| CreaseTag {
        a: t.a + bv,
        b: t.b + bv,
        ..*t
    }));
    out.corners
        .extend(s.corners.iter().map(|t| CornerTag { v: t.v + bv, ..*t }));
    out.holes
        .extend(s.holes.iter().map(|t| HoleTag { f: t.f + bf, ..*t }));
    cage.prims.push(prim);
    Ok(())
}

/// Appends the primvars of `one` (prim `prim`) to those of `out` (first prim `first`): the
/// same names, widths and interpolations, a constant of several prims as one value per face
/// (uniform); values and element indices appended after `out`'s.
fn merge_primvars(
    out: &mut PolygonSoup,
    one: &PolygonSoup,
    file: &str,
    first: &str,
    prim: &str,
) -> Result<(), UsdError> {
    use crate::PrimvarInterpolation as I;
    let names = |s: &PolygonSoup| {
        let mut n: Vec<String> = s.primvars.iter().map(|p| p.name.clone()).collect();
        n.sort();
        n
    };
    let mixed = |a: String, b: String| UsdError::Mixed {
        path: file.to_string(),
        attr: "primvars",
        a: format!("{first} ({a})"),
        b: format!("{prim} ({b})"),
    };
    if names(out) != names(one) {
        return Err(mixed(names(out).join(" "), names(one).join(" ")));
    }
    let uniform = |p: &mut crate::Primvar, faces: usize| {
        if p.interpolation == I::Constant {
            p.interpolation = I::Uniform;
            p.indices = vec![p.indices[0]; faces];
        }
    };
    let faces_out = out.num_faces();
    for p in &mut out.primvars {
        let Some(q) = one.primvars.iter().find(|q| q.name == p.name) else {
            continue;
        };
        let mut q = q.clone();
        uniform(p, faces_out);
        uniform(&mut q, one.num_faces());
        if p.interpolation != q.interpolation || p.width != q.width {
            let show = |p: &crate::Primvar| {
                format!(
                    "{} {} of width {}",
                    p.name,
                    p.interpolation.token(),
                    p.width
                )
            };
            return Err(mixed(show(p), show(&q)));
        }
        let base = p.num_values() as u32;
        p.values.extend_from_slice(&q.values);
        p.indices.extend(q.indices.iter().map(|&i| i + base));
    }
    Ok(())
}

/// The USD attribute a validation error is about.
fn attribute_of(err: &MeshError) -> &'static str {
    match err {
        MeshError::NonFinite { .. } => "points",
        MeshError::TagMissingEdge { .. } => "creaseIndices",
        MeshError::TagMissingVertex { tag, .. } if *tag == "crease" => "creaseIndices",
        MeshError::TagMissingVertex { .. } => "cornerIndices",
        MeshError::TagMissingFace { .. } => "holeIndices",
        MeshError::BadSharpness { tag, .. } if *tag == "corner" => "cornerSharpnesses",
        MeshError::BadSharpness { .. } => "creaseSharpnesses",
        MeshError::UvIndexOutOfRange { .. } | MeshError::UvCount { .. } => "primvars:st:indices",
        MeshError::NonFiniteUv { .. } => "primvars:st",
        _ => "faceVertexIndices",
    }
}
