//! The parameter points of a uniform refinement: which `(face, u, v)` each vertex of the
//! level-`d` mesh of `subdiv_rules::refine_uniform` is the limit of.

use subdiv_mesh::Mesh;
use subdiv_rules::{Depth, Scheme};

use crate::Domain;

type Param = [f64; 2];

fn mid(a: Param, b: Param) -> Param {
    [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
}

/// Every face of the level-`depth` refinement, in `subdiv_rules::refine_uniform`'s order: the
/// cage face it lies in and the `(u, v)` of its corners in that face's [`Domain`]. (A
/// Catmull-Clark or bilinear cage with a face that is not a quad is split whole at level 1, an n-gon into
/// its sub-faces; a Loop triangle's children are its three corners' and the middle one.)
pub fn refined_faces(mesh: &Mesh, scheme: Scheme, depth: Depth) -> Vec<(u32, Vec<Param>)> {
    let ngons = scheme != Scheme::Loop && mesh.faces().any(|f| mesh.face_size(f) != 4);
    let mut faces: Vec<(u32, Vec<Param>)> = Vec::with_capacity(mesh.num_faces());
    for f in mesh.faces() {
        let n = mesh.face_size(f);
        let d = Domain::of(scheme, n);
        let c: Vec<Param> = (0..n).map(|k| d.corner(k)).collect();
        match d {
            Domain::SubFaces { .. } if depth > 0 => {
                for &[x, y] in &c {
                    let sub = vec![[x, y], [x + 0.5, y], [x + 0.5, y + 0.5], [x, y + 0.5]];
                    faces.push((f.0, sub));
                }
            }
            Domain::Quad if ngons && depth > 0 => {
                faces.extend(children(&c).into_iter().map(|p| (f.0, p)));
            }
            _ => faces.push((f.0, c)),
        }
    }
    for _ in u8::from(ngons).min(depth)..depth {
        faces = faces
            .into_iter()
            .flat_map(|(face, p)| children(&p).into_iter().map(move |c| (face, c)))
            .collect();
    }
    faces
}

/// The children of a face with corner parameters `p`, as `refine_uniform` orders them.
fn children(p: &[Param]) -> Vec<Vec<Param>> {
    if p.len() == 3 {
        let (ab, bc, ca) = (mid(p[0], p[1]), mid(p[1], p[2]), mid(p[2], p[0]));
        return vec![
            vec![p[0], ab, ca],
            vec![p[1], bc, ab],
            vec![p[2], ca, bc],
            vec![ab, bc, ca],
        ];
    }
    let c = mid(mid(p[0], p[2]), mid(p[1], p[3]));
    (0..4)
        .map(|k| {
            vec![
                p[k],
                mid(p[k], p[(k + 1) % 4]),
                c,
                mid(p[(k + 3) % 4], p[k]),
            ]
        })
        .collect()
}
