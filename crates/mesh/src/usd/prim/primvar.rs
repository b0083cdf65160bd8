//! `primvars:st`: a mesh prim's texture coordinates as the soup's face-varying channel; every
//! other `primvars:*` as a [`Primvar`].
//!
//! `faceVarying` values (one per face corner, or through `primvars:st:indices`) become the
//! channel as they are, so corners with different values make seams; `vertex` and `varying`
//! values (one per point) give every corner its point's value (no seams; both are then refined
//! by the face-varying rules, which for `varying`, linear in USD, is an approximation). Other
//! interpolations (`constant`, `uniform`), other value types and counts or indices that do not
//! fit are errors naming the prim and the attribute.

use glam::Vec2;
use openusd::sdf::Value;

use super::Reader;
use crate::error::UsdError;
use crate::primvar::{Primvar, PrimvarInterpolation};
use crate::soup::PolygonSoup;

const ST: &str = "primvars:st";
const ST_INDICES: &str = "primvars:st:indices";

/// How a primvar's values map to a mesh (its `interpolation` metadata).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Interpolation {
    FaceVarying,
    Vertex,
}

impl Reader<'_> {
    /// Reads `primvars:st` into `soup.uvs`/`soup.uv_indices` (nothing when not authored), after
    /// [`Reader::faces`]: `flip` reverses each face's corners as it did.
    pub(super) fn texture_coordinates(
        &self,
        soup: &mut PolygonSoup,
        flip: bool,
    ) -> Result<(), UsdError> {
        let values: Vec<Vec2> = match self.value(ST)? {
            None => return Ok(()),
            Some(Value::Vec2fVec(v)) => v.iter().map(|t| Vec2::new(t.x, t.y)).collect(),
            Some(Value::Vec2dVec(v)) => v
                .iter()
                .map(|t| Vec2::new(t.x as f32, t.y as f32))
                .collect(),
            Some(Value::Vec2hVec(v)) => v
                .iter()
                .map(|t| Vec2::new(t.x.to_f32(), t.y.to_f32()))
                .collect(),
            Some(v) => return Err(self.wrong_type(ST, "texCoord2f[]", &v)),
        };
        if let Some(bad) = values.iter().position(|t| !t.is_finite()) {
            return Err(self.err(ST, format!("value {bad} is not finite")));
        }
        let interpolation = self.interpolation()?;
        let indices = self.ints(ST_INDICES)?;
        let authored_indices = !indices.is_empty();
        // The value index of each element (corner or point).
        let elements = match interpolation {
            Interpolation::FaceVarying => soup.face_indices.len(),
            Interpolation::Vertex => soup.positions.len(),
        };
        let what = match interpolation {
            Interpolation::FaceVarying => "face corners (faceVertexIndices)",
            Interpolation::Vertex => "points",
        };
        let per_element: Vec<i64> = if authored_indices {
            if indices.len() != elements {
                return Err(self.err(
                    ST_INDICES,
                    format!("{} indices for {elements} {what}", indices.len()),
                ));
            }
            if let Some(k) = indices
                .iter()
                .position(|&i| i < 0 || i as usize >= values.len())
            {
                return Err(self.err(
                    ST_INDICES,
                    format!(
                        "index {k} is {}, outside the {} values of {ST}",
                        indices[k],
                        values.len()
                    ),
                ));
            }
            indices
        } else {
            if values.len() != elements {
                return Err(self.err(ST, format!("{} values for {elements} {what}", values.len())));
            }
            (0..elements as i64).collect()
        };
        let corners: Vec<i64> = match interpolation {
            Interpolation::Vertex => soup
                .face_indices
                .iter()
                // A bad point index is left to validation (it names the face).
                .map(|&v| {
                    usize::try_from(v)
                        .ok()
                        .and_then(|v| per_element.get(v).copied())
                        .unwrap_or(-1)
                })
                .collect(),
            Interpolation::FaceVarying if flip => {
                // The faces were rewound (vertex 0 kept, the rest reversed): so are their corners.
                let mut out = Vec::with_capacity(per_element.len());
                for f in 0..soup.num_faces() {
                    let r = soup.face_offsets[f] as usize..soup.face_offsets[f + 1] as usize;
                    let face = &per_element[r];
                    if let Some((&first, rest)) = face.split_first() {
                        out.push(first);
                        out.extend(rest.iter().rev());
                    }
                }
                out
            }
            Interpolation::FaceVarying => per_element,
        };
        soup.uvs = values;
        soup.uv_indices = corners;
        Ok(())
    }

    /// The `interpolation` metadata of `primvars:st` (USD's default is `constant`).
    fn interpolation(&self) -> Result<Interpolation, UsdError> {
        let sp = openusd::sdf::path(self.path).map_err(|e| self.err(ST, format!("{e:#}")))?;
        let attr = self.stage.prim(sp).attribute(ST);
        let token = match attr
            .get_metadata::<Value>("interpolation")
            .map_err(|e| self.err(ST, format!("interpolation: {e:#}")))?
        {
            None => "constant".to_string(),
            Some(Value::Token(t)) => t.as_str().to_string(),
            Some(Value::String(s)) => s,
            Some(v) => return Err(self.wrong_type(ST, "interpolation token", &v)),
        };
        match token.as_str() {
            "faceVarying" => Ok(Interpolation::FaceVarying),
            "vertex" | "varying" => Ok(Interpolation::Vertex),
            other => Err(self.err(
                ST,
                format!(
                    "interpolation '{other}' is not supported for texture coordinates \
                     (faceVarying, vertex or varying)"
                ),
            )),
        }
    }
}

/// A primvar's values as `(width, floats)`: scalars and vectors of 1 to 4 components of any
/// precision, one value or an array; `None` for other value types.
fn floats_of(v: &Value) -> Option<(usize, Vec<f32>)> {
    macro_rules! flat {
        ($vec:expr, $w:expr, |$t:ident| $body:expr) => {
            Some(($w, $vec.iter().flat_map(|$t| $body).collect()))
        };
    }
    match v {
        Value::Float(x) => Some((1, vec![*x])),
        Value::Double(x) => Some((1, vec![*x as f32])),
        Value::Half(x) => Some((1, vec![x.to_f32()])),
        Value::FloatVec(v) => Some((1, v.clone())),
        Value::DoubleVec(v) => flat!(v, 1, |x| [*x as f32]),
        Value::HalfVec(v) => flat!(v, 1, |x| [x.to_f32()]),
        Value::Vec2f(t) => Some((2, vec![t.x, t.y])),
        Value::Vec2d(t) => Some((2, vec![t.x as f32, t.y as f32])),
        Value::Vec2fVec(v) => flat!(v, 2, |t| [t.x, t.y]),
        Value::Vec2dVec(v) => flat!(v, 2, |t| [t.x as f32, t.y as f32]),
        Value::Vec2hVec(v) => flat!(v, 2, |t| [t.x.to_f32(), t.y.to_f32()]),
        Value::Vec3f(t) => Some((3, vec![t.x, t.y, t.z])),
        Value::Vec3d(t) => Some((3, vec![t.x as f32, t.y as f32, t.z as f32])),
        Value::Vec3fVec(v) => flat!(v, 3, |t| [t.x, t.y, t.z]),
        Value::Vec3dVec(v) => flat!(v, 3, |t| [t.x as f32, t.y as f32, t.z as f32]),
        Value::Vec3hVec(v) => flat!(v, 3, |t| [t.x.to_f32(), t.y.to_f32(), t.z.to_f32()]),
        Value::Vec4f(t) => Some((4, vec![t.x, t.y, t.z, t.w])),
        Value::Vec4d(t) => Some((4, vec![t.x as f32, t.y as f32, t.z as f32, t.w as f32])),
        Value::Vec4fVec(v) => flat!(v, 4, |t| [t.x, t.y, t.z, t.w]),
        Value::Vec4dVec(v) => flat!(v, 4, |t| [t.x as f32, t.y as f32, t.z as f32, t.w as f32]),
        Value::Vec4hVec(v) => {
            flat!(v, 4, |t| [
                t.x.to_f32(),
                t.y.to_f32(),
                t.z.to_f32(),
                t.w.to_f32()
            ])
        }
        _ => None,
    }
}

impl Reader<'_> {
    /// Every `primvars:NAME` of the prim but `st` (the texture coordinates) and the `:indices`
    /// attributes, after [`Reader::faces`] (`flip` reverses face-varying corners as it did the
    /// faces): its values, width (components times `elementSize`), interpolation (USD's
    /// default `constant`) and indices (`primvars:NAME:indices`, else one value per element).
    /// Values of other types (strings, tokens, matrices) are an error naming the attribute.
    pub(super) fn primvars(
        &self,
        soup: &PolygonSoup,
        flip: bool,
    ) -> Result<Vec<Primvar>, UsdError> {
        let sp =
            openusd::sdf::path(self.path).map_err(|e| self.err("primvars", format!("{e:#}")))?;
        let prim = self.stage.prim(sp);
        let names = prim
            .property_names()
            .map_err(|e| self.err("primvars", format!("{e:#}")))?;
        let mut out = Vec::new();
        for name in names {
            let attr = name.as_str();
            let Some(pv) = attr.strip_prefix("primvars:") else {
                continue;
            };
            if pv == "st" || pv.ends_with(":indices") || pv.contains(':') {
                continue;
            }
            let Some(value) = self.value(attr)? else {
                continue;
            };
            let Some((components, values)) = floats_of(&value) else {
                return Err(self.wrong_type(
                    attr,
                    "float, float2, float3 or float4 values",
                    &value,
                ));
            };
            let meta = |key: &str| {
                prim.attribute(attr)
                    .get_metadata::<Value>(key)
                    .map_err(|e| self.err(attr, format!("{key}: {e:#}")))
            };
            let interpolation = match meta("interpolation")? {
                None => PrimvarInterpolation::Constant,
                Some(Value::Token(t)) => {
                    PrimvarInterpolation::from_token(t.as_str()).ok_or_else(|| {
                        self.err(
                            attr,
                            format!("interpolation '{}' is not a USD interpolation", t.as_str()),
                        )
                    })?
                }
                Some(v) => return Err(self.wrong_type(attr, "interpolation token", &v)),
            };
            let element_size = match meta("elementSize")? {
                None => 1,
                Some(Value::Int(n)) if n >= 1 => n as usize,
                Some(v) => {
                    return Err(
                        self.err(attr, format!("elementSize {v:?} is not a positive integer"))
                    );
                }
            };
            let width = components * element_size;
            let n_values = values.len() / width;
            let elements = match interpolation {
                PrimvarInterpolation::Constant => 1,
                PrimvarInterpolation::Uniform => soup.num_faces(),
                PrimvarInterpolation::Vertex | PrimvarInterpolation::Varying => {
                    soup.positions.len()
                }
                PrimvarInterpolation::FaceVarying => soup.face_indices.len(),
            };
            let idx_name = format!("{attr}:indices");
            let authored = self.ints(&idx_name)?;
            let per_element: Vec<i64> = if authored.is_empty() {
                if n_values != elements || values.len() % width != 0 {
                    return Err(self.err(
                        attr,
                        format!(
                            "{n_values} values for {elements} elements ({})",
                            interpolation.token()
                        ),
                    ));
                }
                (0..elements as i64).collect()
            } else {
                if authored.len() != elements {
                    return Err(self.err(
                        &idx_name,
                        format!("{} indices for {elements} elements", authored.len()),
                    ));
                }
                if let Some(k) = authored
                    .iter()
                    .position(|&i| i < 0 || i as usize >= n_values)
                {
                    return Err(self.err(
                        &idx_name,
                        format!(
                            "index {k} is {}, outside the {n_values} values of {attr}",
                            authored[k]
                        ),
                    ));
                }
                authored
            };
            let indices: Vec<i64> = if interpolation == PrimvarInterpolation::FaceVarying && flip {
                let mut out = Vec::with_capacity(per_element.len());
                for f in 0..soup.num_faces() {
                    let r = soup.face_offsets[f] as usize..soup.face_offsets[f + 1] as usize;
                    if let Some((&first, rest)) = per_element[r].split_first() {
                        out.push(first);
                        out.extend(rest.iter().rev());
                    }
                }
                out
            } else {
                per_element
            };
            out.push(Primvar {
                name: pv.to_string(),
                interpolation,
                width,
                values,
                indices: indices.into_iter().map(|i| i as u32).collect(),
            });
        }
        Ok(out)
    }
}
