//! A mesh's primvars ([`Mesh::primvars`]) through a pass: refined with the same selection and
//! closure as the positions and the UVs, as OpenSubdiv's `PrimvarRefiner` refines them under
//! uniform refinement.
//!
//! - **vertex**: three floats at a time stand in for the positions and take the pass's vertex
//!   and edge points ([`crate::pass::field_points`]), read at the pass's level like the
//!   positions (each keeps its previous-level values, [`AdaptiveMesh::previous_primvars`]);
//! - **face-varying**: two floats at a time stand in for the UVs and take their pass
//!   ([`crate::fvar::pass_uvs`]), seams and the mesh's face-varying option included;
//! - **varying**: linear: a vertex keeps its value, an edge point takes the mean of its ends';
//! - **uniform**: each triangle the value of the face it comes from;
//! - **constant**: unchanged.
//!
//! With every face selected a step refines vertex primvars exactly as the positions (a vertex
//! primvar equal to the positions stays equal to them, bit for bit).

use glam::{Vec2, Vec3};
use subdiv_mesh::{Dependence, FaceVarying, Mesh, Primvar, PrimvarInterpolation, VertexId};
use subdiv_rules::{RefineKernel, Scheme};

use crate::RedGreenError;
use crate::fvar::pass_uvs;
use crate::pass::{field_points, level_values};
use crate::red_green::{Assembly, Closure};
use crate::step::AdaptiveMesh;

/// The previous-level values a refinement of `mesh` starts with, per primvar
/// ([`AdaptiveMesh::previous_primvars`]): a vertex primvar's value at every vertex, a
/// face-varying one's values; nothing for the others.
pub(crate) fn initial_previous(mesh: &Mesh) -> Vec<Vec<f32>> {
    mesh.primvars()
        .iter()
        .map(|p| match p.interpolation {
            PrimvarInterpolation::Vertex => per_vertex(mesh, p),
            PrimvarInterpolation::FaceVarying => p.values.clone(),
            _ => Vec::new(),
        })
        .collect()
}

/// `p`'s value at every vertex, `width` floats each.
fn per_vertex(mesh: &Mesh, p: &Primvar) -> Vec<f32> {
    (0..mesh.num_vertices())
        .flat_map(|v| p.element(v).to_vec())
        .collect()
}

/// A primvar refined by a pass: its values, the value of every element and the values'
/// previous-level ones.
type Refined = (Vec<f32>, Vec<u32>, Vec<f32>);

/// The primvars of a pass's child mesh and their previous-level values.
pub(crate) struct PassPrimvars {
    pub primvars: Vec<Primvar>,
    pub previous: Vec<Vec<f32>>,
    /// Per primvar, its values' [`Dependence`] ([`AdaptiveMesh::primvar_dependence`]).
    pub dependence: Vec<Vec<Dependence>>,
}

/// One pass as the primvars read it: `cur` refined by `closure` read at `level` (`None`: the
/// current values), with the pass's midpoints `edge_mid` and triangles `asm`.
pub(crate) struct Pass<'a> {
    pub cur: &'a AdaptiveMesh,
    pub closure: &'a Closure,
    pub level: Option<u8>,
    pub edge_mid: &'a [VertexId],
    pub asm: &'a Assembly,
}

/// Refines the primvars of the pass's mesh: `kernel` has computed the pass's vertex points of
/// the positions (for the face-varying rules' child sharpness).
pub(crate) fn pass_primvars(
    kernel: &mut RefineKernel<'_>,
    pass: &Pass<'_>,
) -> Result<PassPrimvars, RedGreenError> {
    let (cur, closure, level, asm) = (pass.cur, pass.closure, pass.level, pass.asm);
    let mesh = &cur.mesh;
    let mut out = PassPrimvars {
        primvars: Vec::with_capacity(mesh.primvars().len()),
        previous: Vec::with_capacity(mesh.primvars().len()),
        dependence: Vec::with_capacity(mesh.primvars().len()),
    };
    for (k, p) in mesh.primvars().iter().enumerate() {
        let previous = &cur.previous_primvars[k];
        let mut dependence = Vec::new();
        let (values, indices, prev) = match p.interpolation {
            PrimvarInterpolation::Constant => (p.values.clone(), p.indices.clone(), Vec::new()),
            PrimvarInterpolation::Uniform => {
                let idx = asm
                    .source_face
                    .iter()
                    .map(|&f| p.indices[f as usize])
                    .collect();
                (p.values.clone(), idx, Vec::new())
            }
            PrimvarInterpolation::Varying => {
                let mut values = per_vertex(mesh, p);
                let w = p.width;
                for e in mesh.edges().filter(|e| closure.split_edge[e.idx()]) {
                    let [a, b] = mesh.edge_vertices(e);
                    for c in 0..w {
                        let m = (values[a.idx() * w + c] + values[b.idx() * w + c]) * 0.5;
                        values.push(m);
                    }
                }
                let n = values.len() / w;
                (values, (0..n as u32).collect(), Vec::new())
            }
            PrimvarInterpolation::Vertex => {
                let (values, prev) = vertex_pass(cur, closure, level, p, previous);
                let n = values.len() / p.width;
                (values, (0..n as u32).collect(), prev)
            }
            PrimvarInterpolation::FaceVarying => {
                let dep = cur.primvar_dependence.get(k).map_or(&[][..], Vec::as_slice);
                let (refined, child) = face_varying_pass(kernel, pass, p, (previous, dep))?;
                dependence = child;
                refined
            }
        };
        out.primvars.push(Primvar {
            name: p.name.clone(),
            interpolation: p.interpolation,
            width: p.width,
            values,
            indices,
        });
        out.previous.push(prev);
        out.dependence.push(dependence);
    }
    Ok(out)
}

/// Three floats of `values` (`width` a value) from float `at` on, as points.
fn chunk3(values: &[f32], width: usize, at: usize) -> Vec<Vec3> {
    values
        .chunks(width)
        .map(|v| {
            let c = |k: usize| v.get(at + k).copied().unwrap_or(0.0);
            Vec3::new(c(0), c(1), c(2))
        })
        .collect()
}

/// A vertex primvar through the pass, three floats at a time standing in for the positions:
/// its new values at every vertex of the child and their previous-level values.
fn vertex_pass(
    cur: &AdaptiveMesh,
    closure: &Closure,
    level: Option<u8>,
    p: &Primvar,
    previous: &[f32],
) -> (Vec<f32>, Vec<f32>) {
    let (mesh, w) = (&cur.mesh, p.width);
    let now = per_vertex(mesh, p);
    let (mut values, mut prev) = (Vec::new(), Vec::new());
    for at in (0..w).step_by(3) {
        let (field, field_prev) = (chunk3(&now, w, at), chunk3(previous, w, at));
        let mut kmesh = mesh.clone();
        let kpos = match level {
            Some(l) => level_values(cur, l, &field, &field_prev),
            None => field.clone(),
        };
        kmesh.positions_mut().copy_from_slice(&kpos);
        let mut kernel = RefineKernel::new(&kmesh, Scheme::Loop);
        let (new, new_prev) = field_points(
            (&mut kernel, &kpos),
            cur,
            closure,
            level.is_some(),
            &field,
            &field_prev,
        );
        if values.is_empty() {
            values = vec![0.0; new.len() * w];
            prev = vec![0.0; new.len() * w];
        }
        for (i, (q, r)) in new.iter().zip(&new_prev).enumerate() {
            for c in 0..3.min(w - at) {
                values[i * w + at + c] = q[c];
                prev[i * w + at + c] = r[c];
            }
        }
    }
    (values, prev)
}

/// A face-varying primvar through the pass, two floats at a time standing in for the UVs
/// (`previous` and `dependence`: its values' previous ones and their [`Dependence`]): its
/// values, the value of every corner of the child's triangles and the values' previous ones,
/// and the child values' dependence (the same for every pair of floats: it follows the seams).
fn face_varying_pass(
    kernel: &mut RefineKernel<'_>,
    pass: &Pass<'_>,
    p: &Primvar,
    (previous, dependence): (&[f32], &[Dependence]),
) -> Result<(Refined, Vec<Dependence>), RedGreenError> {
    let Pass {
        cur,
        closure,
        level,
        edge_mid,
        asm,
    } = *pass;
    let w = p.width;
    let two = |values: &[f32], at: usize| -> Vec<Vec2> {
        values
            .chunks(w)
            .map(|v| Vec2::new(v[at], v.get(at + 1).copied().unwrap_or(0.0)))
            .collect()
    };
    let mut stand_in = cur.clone();
    let (mut values, mut indices, mut prev) = (Vec::new(), Vec::new(), Vec::new());
    let mut child = Vec::new();
    for at in (0..w).step_by(2) {
        let fv = FaceVarying {
            values: two(&p.values, at),
            indices: p.indices.clone(),
            dependence: dependence.to_vec(),
        };
        stand_in
            .mesh
            .set_uv(Some(fv))
            .map_err(RedGreenError::Internal)?;
        stand_in.previous_uv = two(previous, at);
        let Some(u) = pass_uvs(kernel, &stand_in, closure, level, edge_mid, asm)? else {
            continue;
        };
        let corners: Vec<u32> = u.indices.iter().map(|&i| i as u32).collect();
        if values.is_empty() {
            (values, prev) = (vec![0.0; u.values.len() * w], vec![0.0; u.values.len() * w]);
            indices = corners;
            child = u.dependence.clone();
        } else if corners != indices || values.len() != u.values.len() * w {
            return Err(RedGreenError::PrimvarCorners {
                name: p.name.clone(),
            });
        }
        for (i, (q, r)) in u.values.iter().zip(&u.previous).enumerate() {
            for c in 0..2.min(w - at) {
                values[i * w + at + c] = q[c];
                prev[i * w + at + c] = r[c];
            }
        }
    }
    Ok(((values, indices, prev), child))
}
