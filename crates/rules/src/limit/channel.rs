//! [`LimitChannel`]: a primvar evaluated on a tessellated surface, the [`LimitMesh`] methods
//! that hold them, and the stand-in passes every tessellator carries primvars with: vertex ones
//! standing in for the positions ([`vertex_channel`]), the others for the texture coordinates
//! ([`face_varying_channel`]).

use std::collections::HashMap;

use glam::{Vec2, Vec3};
use subdiv_mesh::{FVarLinearInterpolation, FaceVarying, Mesh, Primvar, PrimvarInterpolation};

use super::{LimitMesh, LimitMeshError};

/// A primvar (`subdiv_mesh::Primvar`) on a tessellated surface: `width` floats per value,
/// one value per vertex (vertex and constant primvars: their limit at each limit point) or
/// per face corner through `indices` (face-varying, varying and uniform primvars, whose values
/// differ between the faces at a point on a seam).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LimitChannel {
    /// The primvar's name.
    pub name: String,
    /// Floats per value.
    pub width: usize,
    /// `width` floats per value.
    pub values: Vec<f32>,
    /// The value of every face corner (aligned with [`LimitMesh::face_indices`]), or empty:
    /// one value per vertex, value `i` at vertex `i`.
    pub indices: Vec<u32>,
}

impl LimitChannel {
    /// Whether the channel has one value per vertex (else one per face corner).
    #[inline]
    pub fn per_vertex(&self) -> bool {
        self.indices.is_empty()
    }

    /// Value `i` (`width` floats).
    #[inline]
    pub fn value(&self, i: usize) -> &[f32] {
        &self.values[i * self.width..(i + 1) * self.width]
    }

    /// The value at face corner `c` of a surface with `face_indices`.
    #[inline]
    pub fn at_corner(&self, c: usize, face_indices: &[u32]) -> &[f32] {
        if self.per_vertex() {
            self.value(face_indices[c] as usize)
        } else {
            self.value(self.indices[c] as usize)
        }
    }

    /// Number of values.
    pub fn num_values(&self) -> usize {
        self.values.len() / self.width.max(1)
    }
}

impl LimitMesh {
    /// The primvars evaluated on the surface, in the cage's order.
    #[inline]
    pub fn channels(&self) -> &[LimitChannel] {
        &self.channels
    }

    /// The channel named `name`.
    pub fn channel(&self, name: &str) -> Option<&LimitChannel> {
        self.channels.iter().find(|c| c.name == name)
    }

    /// Adds a channel, checked: a positive width, whole values, one value per vertex or one
    /// index per corner naming a value.
    pub fn push_channel(&mut self, channel: LimitChannel) -> Result<(), LimitMeshError> {
        let bad = |what: String| Err(LimitMeshError(format!("channel {}: {what}", channel.name)));
        if channel.width == 0 || !channel.values.len().is_multiple_of(channel.width) {
            return bad(format!(
                "{} floats for width {}",
                channel.values.len(),
                channel.width
            ));
        }
        let n = channel.num_values();
        if channel.per_vertex() {
            if n != self.positions.len() {
                return bad(format!("{n} values for {} vertices", self.positions.len()));
            }
        } else if channel.indices.len() != self.face_indices.len() {
            return bad(format!(
                "{} indices for {} corners",
                channel.indices.len(),
                self.face_indices.len()
            ));
        } else if let Some(i) = channel.indices.iter().find(|&&i| i as usize >= n) {
            return bad(format!("index {i} for {n} values"));
        }
        self.channels.push(channel);
        Ok(())
    }

    /// Drops every channel.
    pub fn clear_channels(&mut self) {
        self.channels.clear();
    }
}

/// The cage whose positions a vertex primvar's values stand in for ([`vertex_channel`]): `mesh`
/// without face-varying data or primvars (its seams and numbering are the surface's).
pub fn stand_in_base(mesh: &Mesh) -> Mesh {
    let mut base = mesh.clone();
    base.clear_uv();
    base.clear_primvars();
    base
}

/// The channel of the vertex primvar `p` of a surface whose points `points(cage)` gives for a
/// cage of `base`'s topology ([`stand_in_base`]): `p`'s values, three floats at a time, stand
/// in for the positions, so every point gets their limit with the positions' masks (sharpness
/// included), as OpenSubdiv's `Interpolate` then `Limit` give it. The uniform tessellations and
/// the adaptive frames (`subdiv-stitch`) share it.
pub fn vertex_channel<E>(
    base: &Mesh,
    p: &Primvar,
    mut points: impl FnMut(&Mesh) -> Result<Vec<[f32; 3]>, E>,
) -> Result<LimitChannel, E> {
    let w = p.width;
    let mut values = Vec::new();
    let mut stand_in = base.clone();
    for chunk in 0..w.div_ceil(3) {
        for (v, q) in stand_in.positions_mut().iter_mut().enumerate() {
            let e = p.element(v);
            let c = |k: usize| e.get(3 * chunk + k).copied().unwrap_or(0.0);
            *q = Vec3::new(c(0), c(1), c(2));
        }
        let points = points(&stand_in)?;
        if values.is_empty() {
            values = vec![0.0; points.len() * w];
        }
        for (i, q) in points.iter().enumerate() {
            for k in 0..3.min(w - 3 * chunk) {
                values[i * w + 3 * chunk + k] = q[k];
            }
        }
    }
    Ok(LimitChannel {
        name: p.name.clone(),
        width: w,
        values,
        indices: Vec::new(),
    })
}

/// The channel of a varying, uniform or face-varying primvar `p` of `mesh` (one value per
/// face corner of the surface): its values, two floats at a time, stand in for the cage's
/// texture coordinates under the face-varying option its kind takes (face-varying: the cage's;
/// varying and uniform: `All`, linear everywhere), and `pass(stand_in)` gives the surface's
/// face-varying values and the value of every corner for that cage (the uniform tessellations'
/// UVs, an adaptive frame's, or a tessellation's at any rate). Any other kind of primvar is read as a
/// uniform one.
pub fn face_varying_channel<E: From<crate::RulesError>>(
    mesh: &Mesh,
    p: &Primvar,
    mut pass: impl FnMut(&Mesh) -> Result<(Vec<[f32; 2]>, Vec<u32>), E>,
) -> Result<LimitChannel, E> {
    let option = match p.interpolation {
        PrimvarInterpolation::FaceVarying => mesh.options().fvar,
        _ => FVarLinearInterpolation::All,
    };
    // The value of every corner: the corner's, the vertex's or the face's.
    let (offsets, verts) = mesh.face_lists();
    let corner_element: Vec<u32> = match p.interpolation {
        PrimvarInterpolation::FaceVarying => (0..verts.len() as u32).collect(),
        PrimvarInterpolation::Varying => verts.iter().map(|v| v.0).collect(),
        _ => (0..mesh.num_faces())
            .flat_map(|f| std::iter::repeat_n(f as u32, (offsets[f + 1] - offsets[f]) as usize))
            .collect(),
    };
    let indices: Vec<u32> = corner_element
        .iter()
        .map(|&e| p.indices[e as usize])
        .collect();
    let w = p.width;
    let mut stand_in = mesh.clone();
    stand_in.set_fvar_option(option);
    let mut passes: Vec<(Vec<[f32; 2]>, Vec<u32>)> = Vec::new();
    for chunk in 0..w.div_ceil(2) {
        let values = (0..p.num_values())
            .map(|i| {
                let c = |k: usize| p.values.get(i * w + 2 * chunk + k).copied();
                let second = if 2 * chunk + 1 < w { c(1) } else { None };
                Vec2::new(c(0).unwrap_or(0.0), second.unwrap_or(0.0))
            })
            .collect();
        let fv = FaceVarying {
            values,
            indices: indices.clone(),
            dependence: Vec::new(),
        };
        stand_in
            .set_uv(Some(fv))
            .map_err(crate::RulesError::Internal)?;
        passes.push(pass(&stand_in)?);
    }
    // One value per distinct tuple of the passes' values at a corner.
    let corners = passes.first().map_or(0, |p| p.1.len());
    let mut ids: HashMap<Vec<u32>, u32> = HashMap::new();
    let (mut values, mut out_indices) = (Vec::new(), Vec::with_capacity(corners));
    let mut key = Vec::with_capacity(passes.len());
    for c in 0..corners {
        key.clear();
        key.extend(passes.iter().map(|(_, idx)| idx[c]));
        let next = ids.len() as u32;
        let id = *ids.entry(key.clone()).or_insert_with(|| {
            for (chunk, (uvs, idx)) in passes.iter().enumerate() {
                let t = uvs[idx[c] as usize];
                values.push(t[0]);
                if 2 * chunk + 1 < w {
                    values.push(t[1]);
                }
            }
            next
        });
        out_indices.push(id);
    }
    Ok(LimitChannel {
        name: p.name.clone(),
        width: w,
        values,
        indices: out_indices,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channels_are_checked_and_split_with_their_corners() {
        let p = |x: f32, y: f32| [x, y, 0.0];
        let mut m = LimitMesh::new(
            vec![
                p(0.0, 0.0),
                p(1.0, 0.0),
                p(1.0, 1.0),
                p(0.0, 1.0),
                p(2.0, 0.0),
            ],
            vec![[0.0, 0.0, 1.0]; 5],
            vec![0, 4, 7],
            vec![0, 1, 2, 3, 1, 4, 2],
        )
        .unwrap();
        let per_vertex = LimitChannel {
            name: "displayColor".into(),
            width: 3,
            values: (0..15).map(|x| x as f32).collect(),
            indices: Vec::new(),
        };
        m.push_channel(per_vertex.clone()).unwrap();
        // One value per face: the corners of vertices 1 and 2 differ between the faces.
        let per_face = LimitChannel {
            name: "opacity".into(),
            width: 1,
            values: vec![0.25, 0.75],
            indices: vec![0, 0, 0, 0, 1, 1, 1],
        };
        m.push_channel(per_face.clone()).unwrap();
        let wrong = LimitChannel {
            indices: vec![0; 6],
            ..per_face.clone()
        };
        assert!(m.push_channel(wrong).is_err());
        let short = LimitChannel {
            values: vec![0.0; 12],
            ..per_vertex.clone()
        };
        assert!(m.push_channel(short).is_err());
        // The split form: a vertex per distinct (vertex, value); every channel per vertex.
        let s = m.split_sided(true);
        assert_eq!(s.num_vertices(), 7);
        let (c, o) = (
            s.channel("displayColor").unwrap(),
            s.channel("opacity").unwrap(),
        );
        assert!(c.per_vertex() && o.per_vertex());
        for t in 0..s.num_faces() {
            for (k, &v) in s.face(t).iter().enumerate() {
                let orig = m.face_indices()[if t == 0 {
                    [0, 1, 2][k]
                } else if t == 1 {
                    [0, 2, 3][k]
                } else {
                    [4, 5, 6][k]
                }] as usize;
                assert_eq!(c.value(v as usize), per_vertex.value(orig));
            }
            let want = if t < 2 { 0.25 } else { 0.75 };
            assert!(s.face(t).iter().all(|&v| o.value(v as usize) == [want]));
        }
        // Without splitting by corners, per-corner channels are left out.
        let r = m.split_sided(false);
        assert_eq!(r.channels().len(), 1);
        assert_eq!(r.channels()[0].values, per_vertex.values);
    }
}
