//! Primvars through adaptive steps, measured against what they stand in for: a vertex primvar
//! equal to the positions stays the positions and a face-varying one equal to the UVs stays
//! the UVs, bit for bit, at every step of random selections; affine maps of them stay those
//! maps; uniform, varying and constant ones keep their values.

use glam::Vec3;
use subdiv_mesh::{Mesh, Primvar, PrimvarInterpolation as I, parse_obj};
use subdiv_test_support::{Rng, fixture};

use crate::{AdaptiveMesh, loop_step};

/// `text` (OBJ, triangles, with UVs) with primvars: `p` = the positions, `q` an affine map of
/// them (width 4: two passes), `st1` = the UVs, `st2` an affine map of them, `id` the face
/// index (uniform), `seven` 7 at every vertex (varying) and `c` a constant.
fn cage(text: &str) -> Mesh {
    let mut soup = parse_obj(text).unwrap();
    let n = soup.positions.len();
    let faces = soup.face_offsets.len() - 1;
    let flat = |f: &dyn Fn(Vec3) -> Vec<f32>| soup.positions.iter().flat_map(|&p| f(p)).collect();
    let vertex = |name: &str, width: usize, values: Vec<f32>| Primvar {
        name: name.into(),
        interpolation: I::Vertex,
        width,
        values,
        indices: (0..n as u32).collect(),
    };
    let uvs: Vec<f32> = soup.uvs.iter().flat_map(|t| [t.x, t.y]).collect();
    let corners: Vec<u32> = soup.uv_indices.iter().map(|&i| i as u32).collect();
    let fvar = |name: &str, values: Vec<f32>| Primvar {
        name: name.into(),
        interpolation: I::FaceVarying,
        width: 2,
        values,
        indices: corners.clone(),
    };
    let primvars = vec![
        vertex("p", 3, flat(&|p| p.to_array().to_vec())),
        vertex(
            "q",
            4,
            flat(&|p| vec![2.0 * p.y + 1.0, p.z - p.x, 0.5 * p.x, p.x + p.y]),
        ),
        fvar("st1", uvs.clone()),
        fvar(
            "st2",
            uvs.chunks(2)
                .flat_map(|t| [3.0 * t[0] - 1.0, t[1] + 2.0])
                .collect(),
        ),
        Primvar {
            name: "id".into(),
            interpolation: I::Uniform,
            width: 1,
            values: (0..faces).map(|f| f as f32).collect(),
            indices: (0..faces as u32).collect(),
        },
        Primvar {
            name: "seven".into(),
            interpolation: I::Varying,
            width: 1,
            values: vec![7.0],
            indices: vec![0; n],
        },
        Primvar {
            name: "c".into(),
            interpolation: I::Constant,
            width: 2,
            values: vec![0.25, 0.5],
            indices: vec![0],
        },
    ];
    soup.primvars = primvars;
    Mesh::from_soup(&soup).unwrap()
}

/// The cages with seams: a cube's cross unwrap and an octahedron cut in two, triangulated;
/// the octahedron again with `cornersPlus1` and a semi-sharp edge inside each fan at seam
/// vertex 0, one running out a level before the other (`subdiv_mesh::Dependence` is decided on
/// the cage: neither value is ever held; taken afresh at level 1 the other would be), refined
/// whole at every step. With whether every step selects every face.
fn cages() -> Vec<(String, Mesh, bool)> {
    let held = "t crease 2/1/0 0 4 2.5\nt crease 2/1/0 0 5 0.5\n\
                t facevaryinginterpolateboundary 1/0/0 2\n";
    [
        ("meshes/fvar/cube_uv.obj", ""),
        ("meshes/fvar/tri_seam.obj", ""),
        ("meshes/fvar/tri_seam.obj", held),
    ]
    .iter()
    .map(|(path, tags)| {
        let mesh = subdiv_mesh::read_obj(fixture(path)).unwrap();
        let text = subdiv_mesh::format_mesh_obj(&subdiv_mesh::triangulate(&mesh).unwrap());
        let whole = !tags.is_empty();
        let name = format!("{path}{}", if whole { " (semi-sharp fans)" } else { "" });
        (name, cage(&format!("{text}{tags}")), whole)
    })
    .collect()
}

#[test]
fn primvars_follow_what_they_stand_in_for() {
    let mut rng = Rng::splitmix(3);
    for (name, mesh, whole) in cages() {
        let faces = mesh.num_faces();
        let mut a = AdaptiveMesh::new(mesh).unwrap();
        for step in 0..4 {
            let sel: Vec<bool> = (0..a.mesh.num_faces())
                .map(|_| whole || step == 0 || rng.chance(40))
                .collect();
            a = loop_step(&a, &sel).unwrap().0;
            let m = &a.mesh;
            let at = format!("{name} step {step}");
            let get = |n: &str| m.primvar(n).unwrap_or_else(|| panic!("{at}: no {n}"));
            let (p, q) = (get("p"), get("q"));
            let fv = m.uv().unwrap();
            let (st1, st2) = (get("st1"), get("st2"));
            for (v, x) in m.positions().iter().enumerate() {
                assert_eq!(p.element(v), x.to_array(), "{at}: vertex {v}");
                let want = [2.0 * x.y + 1.0, x.z - x.x, 0.5 * x.x, x.x + x.y];
                let got = q.element(v);
                for k in 0..4 {
                    assert!(
                        (got[k] - want[k]).abs() < 1e-5,
                        "{at}: q at {v}: {got:?} {want:?}"
                    );
                }
                assert_eq!(get("seven").element(v), [7.0], "{at}");
            }
            assert_eq!(get("c").element(0), [0.25, 0.5], "{at}");
            assert_eq!(st1.indices.len(), fv.indices.len(), "{at}");
            for (c, &t) in fv.indices.iter().enumerate() {
                let uv = fv.values[t as usize];
                assert_eq!(st1.element(c), uv.to_array(), "{at}: corner {c}");
                let (got, want) = (st2.element(c), [3.0 * uv.x - 1.0, uv.y + 2.0]);
                assert!((got[0] - want[0]).abs() < 1e-5 && (got[1] - want[1]).abs() < 1e-5);
            }
            let id = get("id");
            assert_eq!(id.indices.len(), m.num_faces(), "{at}");
            assert!(id.indices.iter().all(|&i| (i as usize) < faces), "{at}");
        }
    }
}
