//! Reading a cage from any supported file, by extension: USD (`.usd`, `.usda`, `.usdc`,
//! `.usdz`; [`crate::read_usd`]) or OBJ (anything else; [`crate::read_obj_with_warnings`]).

use std::path::Path;

use thiserror::Error;

use crate::error::{ObjError, UsdError};
use crate::mesh::Mesh;
use crate::obj::{ReadOptions, read_obj_with_report};
use crate::tags::TagWarning;
use crate::usd::{FaceVaryingLinear, UsdReadOptions, UsdScheme, is_usd_path, read_usd};

/// Options of [`read_cage`].
#[derive(Clone, Debug, Default)]
pub struct CageOptions {
    /// Repair non-manifold vertices (each fan its own copy, the surface open there) instead of
    /// refining the cage as OpenSubdiv does.
    pub split_nonmanifold_vertices: bool,
    /// USD only: the mesh prim to read (every mesh, merged, without it).
    pub prim: Option<String>,
    /// USD only: the time code to read the stage at (see [`crate::UsdStageReader`]); without
    /// it, default values, else the earliest time samples.
    pub time: Option<f64>,
}

/// A cage and what its file says beyond the mesh.
#[derive(Clone, Debug)]
pub struct Cage {
    /// The validated cage.
    pub mesh: Mesh,
    /// OBJ tag lines read but not applied (always empty for USD).
    pub warnings: Vec<TagWarning>,
    /// USD only: the `subdivisionScheme` the file asks for.
    pub scheme: Option<UsdScheme>,
    /// USD only: the `faceVaryingLinearInterpolation`.
    pub face_varying: Option<FaceVaryingLinear>,
    /// USD only: the mesh prims read.
    pub prims: Vec<String>,
    /// What was non-manifold, refined as OpenSubdiv does (see
    /// [`crate::PolygonSoup::split_nonmanifold`]; empty with `split_nonmanifold_vertices`).
    pub nonmanifold: crate::NonManifold,
}

/// An error of [`read_cage`].
#[derive(Debug, Error)]
pub enum CageError {
    /// Reading an OBJ file.
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// Reading a USD stage.
    #[error(transparent)]
    Usd(#[from] UsdError),
    /// A prim was asked for, but the file is not USD.
    #[error("{path}: a prim ({prim}) can only be chosen in a USD file")]
    PrimNotUsd {
        /// The file.
        path: String,
        /// The prim asked for.
        prim: String,
    },
    /// A time was asked for, but the file is not USD (an OBJ cage does not move).
    #[error("{path}: a time ({time}) can only be chosen in a USD file")]
    TimeNotUsd {
        /// The file.
        path: String,
        /// The time asked for.
        time: f64,
    },
}

/// Reads a cage from an OBJ or USD file, chosen by the extension.
///
/// ```no_run
/// use subdiv_mesh::{CageOptions, read_cage};
/// let cage = read_cage("cage.usdz", &CageOptions::default()).unwrap();
/// println!("{} faces", cage.mesh.num_faces());
/// ```
pub fn read_cage(path: impl AsRef<Path>, opts: &CageOptions) -> Result<Cage, CageError> {
    let path = path.as_ref();
    if is_usd_path(path) {
        let usd = read_usd(
            path,
            &UsdReadOptions {
                prim: opts.prim.clone(),
                split_nonmanifold_vertices: opts.split_nonmanifold_vertices,
                time: opts.time,
            },
        )?;
        return Ok(Cage {
            mesh: usd.mesh,
            warnings: Vec::new(),
            scheme: Some(usd.scheme),
            face_varying: Some(usd.face_varying),
            prims: usd.prims,
            nonmanifold: usd.nonmanifold,
        });
    }
    if let Some(prim) = &opts.prim {
        return Err(CageError::PrimNotUsd {
            path: path.display().to_string(),
            prim: prim.clone(),
        });
    }
    if let Some(time) = opts.time {
        return Err(CageError::TimeNotUsd {
            path: path.display().to_string(),
            time,
        });
    }
    let (mesh, warnings, nonmanifold) = read_obj_with_report(
        path,
        ReadOptions {
            split_nonmanifold_vertices: opts.split_nonmanifold_vertices,
        },
    )?;
    Ok(Cage {
        mesh,
        warnings,
        scheme: None,
        face_varying: None,
        prims: Vec::new(),
        nonmanifold,
    })
}
