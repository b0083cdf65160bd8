//! `primvars:st`: a mesh prim's texture coordinates as the soup's face-varying channel.
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
