//! A cage's primvars on a tessellation at any rate ([`tessellation_primvars`]), as the uniform
//! and adaptive tessellations carry them:
//! - **vertex**: three floats at a time stand in for the cage's positions and are evaluated at
//!   every output point's parameter point, so they get the positions' exact limit
//!   (`subdiv_rules::vertex_channel`);
//! - **face-varying, varying, uniform**: two floats at a time stand in for the cage's texture
//!   coordinates (`subdiv_rules::face_varying_channel`: the cage's face-varying option, or
//!   linear for varying and uniform ones) and are evaluated at every triangle corner's own
//!   parameter point ([`Tessellation::corner_param`]), so a seam keeps each face's value;
//! - **constant**: the one value at every point.

use subdiv_mesh::{Mesh, PrimvarInterpolation};
use subdiv_rules::{LimitChannel, Scheme, face_varying_channel, stand_in_base, vertex_channel};

use crate::tess::corner_values;
use crate::{Derivatives, EvalError, Evaluator, Query, Sample, Tessellation};

/// Adds to `t` (a tessellation of `mesh` under `scheme`, [`crate::tessellate_rates`] or
/// [`crate::dice`]) one channel per primvar of `mesh`.
pub fn tessellation_primvars(
    mesh: &Mesh,
    scheme: Scheme,
    t: &mut Tessellation,
) -> Result<(), EvalError> {
    if mesh.primvars().is_empty() {
        return Ok(());
    }
    let base = stand_in_base(mesh);
    let queries: Vec<Query> = t
        .params
        .iter()
        .map(|&(face, [u, v])| Query::new(face, u, v))
        .collect();
    let mut samples = vec![Sample::default(); queries.len()];
    let mut channels = Vec::new();
    for p in mesh.primvars() {
        channels.push(match p.interpolation {
            PrimvarInterpolation::Constant => LimitChannel {
                name: p.name.clone(),
                width: p.width,
                values: p.element(0).repeat(queries.len()),
                indices: Vec::new(),
            },
            PrimvarInterpolation::Vertex => vertex_channel(&base, p, |cage| {
                let eval = Evaluator::new(cage, scheme)?;
                eval.evaluate_many(&queries, Derivatives::First, &mut samples)?;
                Ok::<_, EvalError>(
                    samples
                        .iter()
                        .map(|s| s.position.as_vec3().to_array())
                        .collect(),
                )
            })?,
            _ => face_varying_channel(mesh, p, |cage| {
                let eval = Evaluator::new(cage, scheme)?;
                corner_values(&eval, t)?
                    .ok_or_else(|| EvalError::Internal("a stand-in cage without values".into()))
            })?,
        });
    }
    for c in channels {
        t.surface
            .push_channel(c)
            .map_err(|e| EvalError::Internal(e.to_string()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use subdiv_mesh::{Primvar, read_obj_soup};
    use subdiv_test_support::{Rng, shape};

    use super::*;
    use crate::{EdgeRates, tessellate_rates};

    /// `name`'s cage with `p` = its positions and `q` an affine map of them (4 floats), and a
    /// uniform primvar.
    fn cage(name: &str) -> Mesh {
        let mut soup = read_obj_soup(shape(name)).unwrap();
        let n = soup.positions.len();
        let faces = soup.face_offsets.len() - 1;
        let vertex = |name: &str, width: usize, values: Vec<f32>| Primvar {
            name: name.into(),
            interpolation: PrimvarInterpolation::Vertex,
            width,
            values,
            indices: (0..n as u32).collect(),
        };
        let p = soup.positions.iter().flat_map(|x| x.to_array()).collect();
        let q = soup
            .positions
            .iter()
            .flat_map(|x| [2.0 * x.y + 1.0, x.z - x.x, 0.5 * x.x, x.x + x.y])
            .collect();
        soup.primvars = vec![
            vertex("p", 3, p),
            vertex("q", 4, q),
            Primvar {
                name: "id".into(),
                interpolation: PrimvarInterpolation::Uniform,
                width: 1,
                values: (0..faces).map(|f| f as f32).collect(),
                indices: (0..faces as u32).collect(),
            },
        ];
        soup.split_nonmanifold().unwrap();
        Mesh::from_soup(&soup).unwrap()
    }

    /// At random rates: a vertex primvar equal to the positions is every output point, bit for
    /// bit, and an affine map of them is that map of the points.
    #[test]
    fn vertex_primvars_are_evaluated_at_every_point() {
        let mut rng = Rng::splitmix(8);
        for (name, scheme) in [
            ("catmark_pawn.obj", Scheme::CatmullClark),
            ("catmark_nonquads.obj", Scheme::CatmullClark),
            ("loop_cubes_semisharp.obj", Scheme::Loop),
        ] {
            let mesh = cage(name);
            let eval = Evaluator::new(&mesh, scheme).unwrap();
            let rates: Vec<u32> = (0..mesh.num_edges())
                .map(|_| 1 + rng.below(6) as u32)
                .collect();
            let mut t = tessellate_rates(&eval, &EdgeRates::from_rates(rates)).unwrap();
            tessellation_primvars(&mesh, scheme, &mut t).unwrap();
            let s = &t.surface;
            let (p, q) = (s.channel("p").unwrap(), s.channel("q").unwrap());
            // The uniform primvar: each corner its own face's value.
            let id = s.channel("id").unwrap();
            for c in 0..s.face_indices().len() {
                let face = t.corner_param(c).0 as f32;
                assert_eq!(
                    id.at_corner(c, s.face_indices()),
                    [face],
                    "{name}: corner {c}"
                );
            }
            for (v, x) in s.positions().iter().enumerate() {
                assert_eq!(p.value(v), x, "{name}: vertex {v}");
                let want = [2.0 * x[1] + 1.0, x[2] - x[0], 0.5 * x[0], x[0] + x[1]];
                let got = q.value(v);
                for k in 0..4 {
                    assert!(
                        (got[k] - want[k]).abs() < 1e-5,
                        "{name} {v}: {got:?} {want:?}"
                    );
                }
            }
        }
    }
}
