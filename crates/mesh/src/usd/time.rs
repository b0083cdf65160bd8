//! Time on a USD stage: its time range ([`StageTime`]) and an open stage that reads the cage at
//! any time code ([`UsdStageReader`]), for animated cages whose points (or the transforms above
//! them) are time-sampled.
//!
//! USD resolves a value at a time code from the attribute's time samples, linearly
//! interpolated between the two that bracket it and held beyond the first and the last
//! (numeric values; others are held), and falls back to the default value where no sample is
//! authored. A cage read at a time code is read whole at that time (topology and tags too), so
//! a stage whose topology is time-sampled gives the topology of that time.

use std::path::Path;

use openusd::sdf;
use openusd::usd::Stage;

use super::catch::catch_reader;
use super::{UsdCage, UsdMesh, UsdReadOptions, build_cage, merge, mesh_prims, prim_not_found};
use crate::error::UsdError;

/// The time of a stage: its authored range, its rate, and which attributes of the meshes read
/// are time-sampled.
#[derive(Clone, Debug, PartialEq)]
pub struct StageTime {
    /// `startTimeCode` and `endTimeCode`, when the stage authors both.
    pub authored: Option<(f64, f64)>,
    /// `timeCodesPerSecond` (else `framesPerSecond`, else 24, as USD reads it).
    pub time_codes_per_second: f64,
    /// Each time-sampled attribute of the meshes read and of the prims above them (their
    /// transforms), as `/Prim.attribute`, with its sample times (ascending), in traversal order.
    pub sampled: Vec<(String, Vec<f64>)>,
}

impl StageTime {
    /// The range to play: the authored one, else the span of the time samples, else `None`
    /// (nothing is time-sampled).
    pub fn range(&self) -> Option<(f64, f64)> {
        if let Some(r) = self.authored {
            return Some(r);
        }
        let times = self.sampled.iter().flat_map(|(_, t)| t.iter().copied());
        let lo = times.clone().reduce(f64::min)?;
        let hi = times.reduce(f64::max)?;
        Some((lo, hi))
    }

    /// Whether the cage moves: some attribute read has time samples at two different times.
    pub fn is_animated(&self) -> bool {
        self.sampled
            .iter()
            .any(|(_, t)| t.first().zip(t.last()).is_some_and(|(a, b)| a != b))
    }
}

/// An open USD stage and the mesh prims chosen from it, read again at any time code.
///
/// ```no_run
/// use subdiv_mesh::{UsdReadOptions, UsdStageReader};
/// let stage = UsdStageReader::open("pawn_bend.usdc", &UsdReadOptions::default()).unwrap();
/// let (start, end) = stage.time().unwrap().range().unwrap();
/// for t in [start, end] {
///     let cage = stage.read_at(Some(t)).unwrap();
///     println!("{t}: {:?}", cage.mesh.position(subdiv_mesh::VertexId(0)));
/// }
/// ```
pub struct UsdStageReader {
    file: String,
    /// Dropped inside the reader's panic boundary (see `Drop`).
    stage: Option<Stage>,
    prims: Vec<String>,
    split_nonmanifold_vertices: bool,
}

impl std::fmt::Debug for UsdStageReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("UsdStageReader")
            .field("file", &self.file)
            .field("prims", &self.prims)
            .finish_non_exhaustive()
    }
}

impl UsdStageReader {
    /// Opens the stage, chooses its mesh prims ([`UsdReadOptions::prim`], else every mesh) and
    /// reads its time (the options' `time` is not used: each read names its own).
    pub fn open(path: impl AsRef<Path>, opts: &UsdReadOptions) -> Result<Self, UsdError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        if let Err(source) = std::fs::metadata(path) {
            return Err(UsdError::Io { path: file, source });
        }
        let (stage, prims) = catch_reader(&file, |doing| {
            let stage = Stage::open(&file).map_err(|e| UsdError::Open {
                path: file.clone(),
                msg: format!("{e:#}"),
            })?;
            doing.set("listing the mesh prims");
            let meshes = mesh_prims(&stage, &file)?;
            let prims = match &opts.prim {
                Some(p) if !meshes.iter().any(|m| m == p) => {
                    doing.set(format!("looking up prim {p}"));
                    return Err(prim_not_found(&stage, &file, p, &meshes));
                }
                Some(p) => vec![p.clone()],
                None if meshes.is_empty() => {
                    return Err(UsdError::NoMesh { path: file.clone() });
                }
                None => meshes,
            };
            Ok((stage, prims))
        })?;
        Ok(UsdStageReader {
            file,
            stage: Some(stage),
            prims,
            split_nonmanifold_vertices: opts.split_nonmanifold_vertices,
        })
    }

    /// The stage's time range and what of the chosen meshes is time-sampled.
    pub fn time(&self) -> Result<StageTime, UsdError> {
        let stage = self.stage()?;
        catch_reader(&self.file, |doing| {
            doing.set("reading the time samples");
            stage_time(stage, &self.file, &self.prims)
        })
    }

    fn stage(&self) -> Result<&Stage, UsdError> {
        self.stage.as_ref().ok_or_else(|| UsdError::NoMesh {
            path: self.file.clone(),
        })
    }

    /// The mesh prims read, in order.
    pub fn prims(&self) -> &[String] {
        &self.prims
    }

    /// The chosen prims at time code `time` as one soup, not validated as a whole (each prim
    /// is); `None` reads default values, else the earliest time samples.
    pub fn read_soup_at(&self, time: Option<f64>) -> Result<UsdCage, UsdError> {
        if let Some(t) = time.filter(|t| !t.is_finite()) {
            return Err(UsdError::Time {
                path: self.file.clone(),
                time: t,
            });
        }
        let stage = self.stage()?;
        let read = catch_reader(&self.file, |doing| {
            let mut read = Vec::new();
            for p in &self.prims {
                doing.set(format!("reading prim {p}"));
                let one = super::prim::read_mesh_prim(stage, &self.file, p, time);
                let failed = one.is_err();
                read.push((p.clone(), one));
                if failed {
                    break;
                }
            }
            Ok(read)
        })?;
        let mut cage = UsdCage::default();
        for (p, one) in read {
            let one = one?;
            super::check_prim(&self.file, &p, &one.soup)?;
            merge(&mut cage, one, &self.file)?;
        }
        Ok(cage)
    }

    /// The validated cage at time code `time` (`None`: default values, else the earliest time
    /// samples).
    pub fn read_at(&self, time: Option<f64>) -> Result<UsdMesh, UsdError> {
        let cage = self.read_soup_at(time)?;
        build_cage(&self.file, cage, self.split_nonmanifold_vertices)
    }
}

impl Drop for UsdStageReader {
    fn drop(&mut self) {
        // Closing the stage runs the reader's code too: a panic there is caught and dropped.
        if let Some(stage) = self.stage.take() {
            let _ = catch_reader(&self.file, |doing| {
                doing.set("closing the stage");
                drop(stage);
                Ok(())
            });
        }
    }
}

/// The time of a stage for the meshes `prims`: the authored range and rate, and every
/// time-sampled attribute of those prims and of their ancestors' transform ops.
fn stage_time(stage: &Stage, file: &str, prims: &[String]) -> Result<StageTime, UsdError> {
    let err = |p: &str, msg: String| UsdError::Attribute {
        path: file.to_string(),
        prim: p.to_string(),
        attr: "timeSamples".to_string(),
        msg,
    };
    let mut sampled: Vec<(String, Vec<f64>)> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for p in prims {
        let mut at = sdf::path(p).ok();
        let mut own = true;
        while let Some(path) = at {
            if path == sdf::Path::abs_root() {
                break;
            }
            let prim = stage.prim(path.clone());
            for attr in prim.attributes().map_err(|e| err(p, format!("{e:#}")))? {
                let name = attr.path().as_str().to_string();
                let is_xform = name
                    .rsplit('.')
                    .next()
                    .is_some_and(|n| n.starts_with("xformOp:"));
                if !(own || is_xform) || !seen.insert(name.clone()) {
                    continue;
                }
                let times = attr
                    .time_sample_times()
                    .map_err(|e| err(p, format!("{e:#}")))?;
                if !times.is_empty() {
                    sampled.push((name, times));
                }
            }
            own = false;
            at = path.parent();
        }
    }
    Ok(StageTime {
        authored: stage
            .has_authored_time_code_range()
            .then(|| (stage.start_time_code(), stage.end_time_code())),
        time_codes_per_second: stage.time_codes_per_second(),
        sampled,
    })
}
