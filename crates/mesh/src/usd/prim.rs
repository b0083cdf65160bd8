//! One `UsdGeomMesh` prim as a polygon soup in world space (the mapping in [`crate::usd`]).

use glam::{DVec3, Vec3};
use openusd::gf::Matrix4d;
use openusd::schemas::geom::{Imageable, Xformable};
use openusd::sdf::{self, Value};
use openusd::usd::{Prim, SchemaBase, SchemaKind, Stage, TimeCode};

use super::{FaceVaryingLinear, UsdScheme};
use crate::error::UsdError;
use crate::options::{BoundaryInterpolation, SchemeOptions, TriangleSubdivision};
use crate::soup::{CornerTag, CreaseTag, HoleTag, PolygonSoup};

mod primvar;

/// One mesh prim read: its soup (world space, no groups) and its subdivision attributes.
#[derive(Clone, Debug)]
pub(crate) struct PrimMesh {
    /// The prim's path.
    pub path: String,
    /// Points (world space), faces (counter-clockwise) and tags.
    pub soup: PolygonSoup,
    /// `subdivisionScheme`.
    pub scheme: UsdScheme,
    /// `faceVaryingLinearInterpolation`.
    pub face_varying: FaceVaryingLinear,
}

/// Reads the mesh prim at `path` of `stage` (`file` names the stage in errors) at `time` (see
/// [`Reader::value`]). The soup is not validated.
pub(crate) fn read_mesh_prim(
    stage: &Stage,
    file: &str,
    path: &str,
    time: Option<f64>,
) -> Result<PrimMesh, UsdError> {
    let at = Reader {
        stage,
        file,
        path,
        time,
    };
    let sp = sdf::path(path).map_err(|e| at.err("", format!("invalid prim path: {e:#}")))?;
    let prim = stage.prim(sp);
    let mut soup = PolygonSoup::default();
    let (world, mirrored) = at.local_to_world(&prim)?;
    let points = at.points()?;
    soup.positions = points.iter().map(|&p| transform(&world, p)).collect();
    let left = at.token("orientation", &["rightHanded", "leftHanded"], 0)? == 1;
    at.faces(&mut soup, left != mirrored)?;
    at.texture_coordinates(&mut soup, left != mirrored)?;
    soup.primvars = at.primvars(&soup, left != mirrored)?;
    at.creases(&mut soup)?;
    let corners = at.ints("cornerIndices")?;
    let sharp = at.floats("cornerSharpnesses")?;
    if corners.len() != sharp.len() {
        return Err(at.err(
            "cornerSharpnesses",
            format!("{} values for {} cornerIndices", sharp.len(), corners.len()),
        ));
    }
    soup.corners = corners
        .iter()
        .zip(&sharp)
        .map(|(&v, &sharpness)| CornerTag {
            v,
            sharpness,
            line: None,
        })
        .collect();
    soup.holes = at
        .ints("holeIndices")?
        .into_iter()
        .map(|f| HoleTag { f, line: None })
        .collect();
    soup.options = at.options()?;
    let scheme = match at.token(
        "subdivisionScheme",
        &["catmullClark", "loop", "bilinear", "none"],
        0,
    )? {
        0 => UsdScheme::CatmullClark,
        1 => UsdScheme::Loop,
        2 => UsdScheme::Bilinear,
        _ => UsdScheme::None,
    };
    const FV: [FaceVaryingLinear; 6] = [
        FaceVaryingLinear::None,
        FaceVaryingLinear::CornersOnly,
        FaceVaryingLinear::CornersPlus1,
        FaceVaryingLinear::CornersPlus2,
        FaceVaryingLinear::Boundaries,
        FaceVaryingLinear::All,
    ];
    let fv = at.token(
        "faceVaryingLinearInterpolation",
        &FV.map(FaceVaryingLinear::token),
        2,
    )?;
    // The option the face-varying refinement of `primvars:st` follows (same order; a cage
    // without it keeps the default, as an OBJ cage does).
    if !soup.uv_indices.is_empty() {
        soup.options.fvar = crate::FVarLinearInterpolation::ALL[fv];
    }
    Ok(PrimMesh {
        path: path.to_string(),
        soup,
        scheme,
        face_varying: FV[fv],
    })
}

/// Any prim seen as `Xformable`, to compose its `xformOp`s (ancestors need not be `Xform`s).
struct AnyXformable(Prim);

impl SchemaBase for AnyXformable {
    const KIND: SchemaKind = SchemaKind::ConcreteTyped;
    fn prim(&self) -> &Prim {
        &self.0
    }
}
impl Imageable for AnyXformable {}
impl Xformable for AnyXformable {}

/// `p` (a row vector) times the affine or projective `m`, in `f64`, rounded once to `f32`.
fn transform(m: &Matrix4d, p: DVec3) -> Vec3 {
    let m = &m.0;
    let c = |j: usize| p.x * m[j] + p.y * m[4 + j] + p.z * m[8 + j] + m[12 + j];
    let w = c(3);
    let q = DVec3::new(c(0), c(1), c(2));
    let q = if w != 1.0 && w != 0.0 { q / w } else { q };
    q.as_vec3()
}

/// Reads attributes of one prim, naming file, prim and attribute in errors.
struct Reader<'a> {
    stage: &'a Stage,
    file: &'a str,
    path: &'a str,
    /// The time code to read at; `None`: the default value, else the earliest time sample.
    time: Option<f64>,
}

impl Reader<'_> {
    fn err(&self, attr: &str, msg: String) -> UsdError {
        UsdError::Attribute {
            path: self.file.to_string(),
            prim: self.path.to_string(),
            attr: attr.to_string(),
            msg,
        }
    }

    /// The attribute's value at the reader's time code (its time samples interpolated as USD
    /// does, linearly for numeric values, else its default value); without a time code, its
    /// default value, else its earliest time sample.
    fn value(&self, name: &str) -> Result<Option<Value>, UsdError> {
        let sp = sdf::path(self.path).map_err(|e| self.err(name, format!("{e:#}")))?;
        let attr = self.stage.prim(sp).attribute(name);
        let read = |t: Option<TimeCode>| {
            attr.get_at::<Value>(t)
                .map_err(|e| self.err(name, format!("{e:#}")))
        };
        if let Some(t) = self.time {
            return read(Some(TimeCode::new(t)));
        }
        match read(None)? {
            Some(v) => Ok(Some(v)),
            None => read(Some(TimeCode::EARLIEST)),
        }
    }

    /// The time code transforms are read at: the reader's, else the earliest time sample.
    fn transform_time(&self) -> TimeCode {
        self.time.map_or(TimeCode::EARLIEST, TimeCode::new)
    }

    fn ints(&self, name: &str) -> Result<Vec<i64>, UsdError> {
        Ok(match self.value(name)? {
            None => Vec::new(),
            Some(Value::IntVec(v)) => v.into_iter().map(i64::from).collect(),
            Some(Value::Int64Vec(v)) => v,
            Some(Value::UintVec(v)) => v.into_iter().map(i64::from).collect(),
            Some(v) => return Err(self.wrong_type(name, "int[]", &v)),
        })
    }

    fn floats(&self, name: &str) -> Result<Vec<f32>, UsdError> {
        Ok(match self.value(name)? {
            None => Vec::new(),
            Some(Value::FloatVec(v)) => v,
            Some(Value::DoubleVec(v)) => v.into_iter().map(|x| x as f32).collect(),
            Some(Value::HalfVec(v)) => v.into_iter().map(|x| x.to_f32()).collect(),
            Some(v) => return Err(self.wrong_type(name, "float[]", &v)),
        })
    }

    fn points(&self) -> Result<Vec<DVec3>, UsdError> {
        Ok(match self.value("points")? {
            None => return Err(self.err("points", "not authored".into())),
            Some(Value::Vec3fVec(v)) => v
                .iter()
                .map(|p| DVec3::new(p.x as f64, p.y as f64, p.z as f64))
                .collect(),
            Some(Value::Vec3dVec(v)) => v.iter().map(|p| DVec3::new(p.x, p.y, p.z)).collect(),
            Some(Value::Vec3hVec(v)) => v
                .iter()
                .map(|p| DVec3::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64()))
                .collect(),
            Some(v) => return Err(self.wrong_type("points", "point3f[]", &v)),
        })
    }

    /// The index of the attribute's token in `allowed`, or `default` when it is not authored.
    fn token(&self, name: &str, allowed: &[&str], default: usize) -> Result<usize, UsdError> {
        let t = match self.value(name)? {
            None => return Ok(default),
            Some(Value::Token(t)) => t.as_str().to_string(),
            Some(Value::String(s)) => s,
            Some(v) => return Err(self.wrong_type(name, "token", &v)),
        };
        allowed.iter().position(|a| *a == t).ok_or_else(|| {
            self.err(
                name,
                format!("unsupported value '{t}' (expected {})", allowed.join(", ")),
            )
        })
    }

    fn wrong_type(&self, name: &str, want: &str, v: &Value) -> UsdError {
        let tag: &'static str = v.into();
        self.err(name, format!("expected {want}, found {tag}"))
    }

    /// `faceVertexCounts` and `faceVertexIndices`, each face reversed (vertex 0 first) when
    /// `flip`.
    fn faces(&self, soup: &mut PolygonSoup, flip: bool) -> Result<(), UsdError> {
        let counts = self.ints("faceVertexCounts")?;
        let indices = self.ints("faceVertexIndices")?;
        if counts.is_empty() {
            return Err(self.err("faceVertexCounts", "not authored or empty".into()));
        }
        let mut start = 0usize;
        for (f, &n) in counts.iter().enumerate() {
            let end = usize::try_from(n)
                .ok()
                .and_then(|n| start.checked_add(n))
                .filter(|&e| e <= indices.len())
                .ok_or_else(|| {
                    self.err(
                        "faceVertexCounts",
                        format!(
                            "face {f}: count {n} runs past the {} faceVertexIndices",
                            indices.len()
                        ),
                    )
                })?;
            let face = &indices[start..end];
            if flip && !face.is_empty() {
                soup.push_face(std::iter::once(face[0]).chain(face[1..].iter().rev().copied()));
            } else {
                soup.push_face(face.iter().copied());
            }
            start = end;
        }
        if start != indices.len() {
            return Err(self.err(
                "faceVertexIndices",
                format!(
                    "{} indices, but faceVertexCounts adds up to {start}",
                    indices.len()
                ),
            ));
        }
        Ok(())
    }

    /// `creaseIndices`/`creaseLengths`/`creaseSharpnesses` as one tag per crease edge.
    fn creases(&self, soup: &mut PolygonSoup) -> Result<(), UsdError> {
        let idx = self.ints("creaseIndices")?;
        let lengths = self.ints("creaseLengths")?;
        let sharp = self.floats("creaseSharpnesses")?;
        let mut edges = 0usize;
        let mut total = 0usize;
        for (c, &n) in lengths.iter().enumerate() {
            let n = usize::try_from(n).ok().filter(|&n| n >= 2).ok_or_else(|| {
                self.err(
                    "creaseLengths",
                    format!("crease {c} has length {n}; a crease needs at least 2 vertices"),
                )
            })?;
            total = total.saturating_add(n);
            edges += n - 1;
        }
        if total != idx.len() {
            return Err(self.err(
                "creaseIndices",
                format!(
                    "{} indices, but creaseLengths adds up to {total}",
                    idx.len()
                ),
            ));
        }
        let per_edge = sharp.len() == edges && sharp.len() != lengths.len();
        if !per_edge && sharp.len() != lengths.len() {
            return Err(self.err(
                "creaseSharpnesses",
                format!(
                    "{} values; expected one per crease ({}) or one per crease edge ({edges})",
                    sharp.len(),
                    lengths.len()
                ),
            ));
        }
        let (mut start, mut e) = (0usize, 0usize);
        for (c, &n) in lengths.iter().enumerate() {
            let chain = &idx[start..start + n as usize];
            for w in chain.windows(2) {
                let sharpness = if per_edge { sharp[e] } else { sharp[c] };
                soup.creases.push(CreaseTag {
                    a: w[0],
                    b: w[1],
                    sharpness,
                    line: None,
                });
                e += 1;
            }
            start += n as usize;
        }
        Ok(())
    }

    /// `interpolateBoundary` and `triangleSubdivisionRule` (USD's creasing is uniform).
    fn options(&self) -> Result<SchemeOptions, UsdError> {
        let boundary = match self.token(
            "interpolateBoundary",
            &["none", "edgeOnly", "edgeAndCorner"],
            2,
        )? {
            0 => BoundaryInterpolation::None,
            1 => BoundaryInterpolation::EdgeOnly,
            _ => BoundaryInterpolation::EdgeAndCorner,
        };
        let triangles =
            match self.token("triangleSubdivisionRule", &["catmullClark", "smooth"], 0)? {
                0 => TriangleSubdivision::Catmark,
                _ => TriangleSubdivision::Smooth,
            };
        Ok(SchemeOptions {
            boundary,
            triangles,
            ..Default::default()
        })
    }

    /// The prim's local-to-world matrix (its ops, then its ancestors' up to the root or a
    /// `!resetXformStack!`) and whether it mirrors (negative determinant).
    fn local_to_world(&self, prim: &Prim) -> Result<(Matrix4d, bool), UsdError> {
        let mut m = Matrix4d::IDENTITY;
        let mut at = Some(prim.path().clone());
        while let Some(p) = at {
            if p == sdf::Path::abs_root() {
                break;
            }
            let x = AnyXformable(self.stage.prim(p.clone()));
            let name = format!("xformOpOrder (of {})", p.as_str());
            let local = x
                .local_to_parent_transform(self.transform_time())
                .map_err(|e| self.err(&name, format!("{e:#}")))?;
            // Row vectors: the prim's own ops apply first, its parent's after.
            m = m * local;
            let reset = x
                .resets_xform_stack()
                .map_err(|e| self.err(&name, format!("{e:#}")))?;
            at = if reset { None } else { p.parent() };
        }
        let a = &m.0;
        let det = a[0] * (a[5] * a[10] - a[6] * a[9]) - a[1] * (a[4] * a[10] - a[6] * a[8])
            + a[2] * (a[4] * a[9] - a[5] * a[8]);
        if !det.is_finite() || det == 0.0 {
            return Err(self.err(
                "xformOpOrder",
                format!("the local-to-world transform is singular (determinant {det})"),
            ));
        }
        Ok((m, det < 0.0))
    }
}
