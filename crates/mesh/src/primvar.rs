//! Primvars: named data of any width a cage carries beside its positions (USD `primvars:*`,
//! OBJ vertex colours), each mapped onto the mesh by its interpolation as USD and OpenSubdiv
//! map it. The texture coordinates `st` (OBJ `vt`) are the mesh's face-varying channel
//! ([`crate::FaceVarying`], [`crate::Mesh::uv`]); every other primvar is a [`Primvar`].

/// How a primvar's values map onto a mesh (USD's `interpolation`), and how subdivision carries
/// them (OpenSubdiv's `PrimvarRefiner`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PrimvarInterpolation {
    /// One value for the whole mesh.
    Constant,
    /// One value per face, constant over the face and its descendants.
    Uniform,
    /// One value per vertex, refined with the scheme's vertex rules (sharpness included) and
    /// taken to the limit with its limit masks, as the positions are (`Interpolate`, `Limit`).
    Vertex,
    /// One value per vertex, interpolated linearly within each face (`InterpolateVarying`).
    Varying,
    /// One value per face corner, shared between corners by index (seams where corners of a
    /// vertex differ), refined with the face-varying rules under the mesh's face-varying
    /// option (`InterpolateFaceVarying`, `LimitFaceVarying`).
    FaceVarying,
}

impl PrimvarInterpolation {
    /// USD's token (`constant`, `uniform`, `vertex`, `varying`, `faceVarying`).
    pub fn token(self) -> &'static str {
        match self {
            PrimvarInterpolation::Constant => "constant",
            PrimvarInterpolation::Uniform => "uniform",
            PrimvarInterpolation::Vertex => "vertex",
            PrimvarInterpolation::Varying => "varying",
            PrimvarInterpolation::FaceVarying => "faceVarying",
        }
    }

    /// The interpolation of USD token `t`.
    pub fn from_token(t: &str) -> Option<PrimvarInterpolation> {
        [
            PrimvarInterpolation::Constant,
            PrimvarInterpolation::Uniform,
            PrimvarInterpolation::Vertex,
            PrimvarInterpolation::Varying,
            PrimvarInterpolation::FaceVarying,
        ]
        .into_iter()
        .find(|i| i.token() == t)
    }
}

/// A named primvar of `width` floats per value.
///
/// Invariants (checked by [`crate::Mesh::from_soup`]): `width >= 1`; `values` holds `width`
/// floats per value, all finite; `indices` holds the value of every element, each below the
/// number of values, one element for [`PrimvarInterpolation::Constant`], one per face for
/// `Uniform`, one per vertex for `Vertex` and `Varying`, one per face corner (in the order of
/// [`crate::Mesh::face_vertices`]) for `FaceVarying`.
#[derive(Clone, Debug, PartialEq)]
pub struct Primvar {
    /// The name (USD's without `primvars:`, e.g. `displayColor`).
    pub name: String,
    /// How the values map onto the mesh.
    pub interpolation: PrimvarInterpolation,
    /// Floats per value.
    pub width: usize,
    /// `width` floats per value.
    pub values: Vec<f32>,
    /// The value of every element.
    pub indices: Vec<u32>,
}

impl Primvar {
    /// The value of element `e` (`width` floats).
    #[inline]
    pub fn element(&self, e: usize) -> &[f32] {
        let i = self.indices[e] as usize * self.width;
        &self.values[i..i + self.width]
    }

    /// Number of values.
    pub fn num_values(&self) -> usize {
        self.values.len() / self.width.max(1)
    }

    /// Checks the invariants for a mesh of `vertices`, `faces` and `corners`; the message
    /// says what is wrong.
    pub(crate) fn check(
        &self,
        vertices: usize,
        faces: usize,
        corners: usize,
    ) -> Result<(), String> {
        if self.width == 0 || !self.values.len().is_multiple_of(self.width) {
            return Err(format!(
                "{} floats for values of width {}",
                self.values.len(),
                self.width
            ));
        }
        let elements = match self.interpolation {
            PrimvarInterpolation::Constant => 1,
            PrimvarInterpolation::Uniform => faces,
            PrimvarInterpolation::Vertex | PrimvarInterpolation::Varying => vertices,
            PrimvarInterpolation::FaceVarying => corners,
        };
        if self.indices.len() != elements {
            return Err(format!(
                "{} elements for {elements} ({})",
                self.indices.len(),
                self.interpolation.token()
            ));
        }
        let n = self.num_values();
        if let Some(k) = self.indices.iter().position(|&i| i as usize >= n) {
            return Err(format!(
                "element {k}: index {} is outside the {n} values",
                self.indices[k]
            ));
        }
        if let Some(k) = self.values.iter().position(|x| !x.is_finite()) {
            return Err(format!("value {} is not finite", k / self.width));
        }
        Ok(())
    }
}
