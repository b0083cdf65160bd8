//! Face-varying data on tessellations at any rate (`subdiv::eval::tessellate_rates`, which
//! dicing uses), measured against the uniform slate tessellations (whose UVs agree with
//! OpenSubdiv's `LimitFaceVarying`, `tests/tests/osd_fvar.rs`): at the uniform rate `2^d` the
//! points are the depth-`d` lattice, and every triangle corner's UV must be the uniform
//! tessellation's at that point *in the corner's own face*, so UV seams keep each side's value.
//! A face-varying primvar equal to the UVs gives the UVs (the uniform ones: `subdiv-eval`'s
//! `primvars` tests).

use glam::Vec2;
use subdiv::eval::{Domain, EdgeRates, Evaluator, tessellate_rates, tessellation_primvars};
use subdiv_mesh::{CageOptions, FaceId, Mesh, Primvar, PrimvarInterpolation, read_cage};
use subdiv_rules::{LimitMesh, Scheme, limit_face_varying_exact};
use subdiv_test_support::Rng;
use subdiv_tests::fixtures;

/// The cages: quads with seams, corners and junctions, a dart, a semi-sharp crease (the
/// evaluator is exact where OpenSubdiv's values approximate: compared loosely there), and
/// Loop triangles cut along a loop of edges.
const CAGES: [(&str, Scheme); 4] = [
    ("meshes/fvar/cube_uv.obj", Scheme::CatmullClark),
    ("meshes/fvar/grid_seam.obj", Scheme::CatmullClark),
    ("meshes/fvar/tri_seam.obj", Scheme::Loop),
    ("meshes/fvar/nonmanifold_seam.obj", Scheme::CatmullClark),
];

/// The uniform depth-`d` tessellation's corners of each cage face: `(position, uv)`, its
/// faces in cage order, `4^d` per quad and `n 4^(d-1)` per other face.
fn uniform_corners(mesh: &Mesh, u: &LimitMesh, d: u8) -> Vec<Vec<([f32; 3], [f32; 2])>> {
    let idx = u.face_indices();
    let per_face = idx.len() / u.num_faces();
    let mut next = 0;
    mesh.faces()
        .map(|f| {
            let n = mesh.face_size(f);
            let quads = if n == 4 {
                1 << (2 * d)
            } else {
                n << (2 * (d - 1))
            };
            let range = next * per_face..(next + quads) * per_face;
            next += quads;
            range
                .map(|c| {
                    (
                        u.positions()[idx[c] as usize],
                        u.uvs()[u.uv_indices()[c] as usize],
                    )
                })
                .collect()
        })
        .collect()
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f32>().sqrt()
}

/// At random rates, every corner at a cage vertex has the face-varying limit of its own
/// face's value there (`subdiv_rules::limit_face_varying_exact`), on every cage, Loop too.
#[test]
fn corners_at_cage_vertices_have_their_faces_limit_values() {
    let mut rng = Rng::splitmix(11);
    for (rel, scheme) in CAGES {
        let mesh = read_cage(fixtures().join(rel), &CageOptions::default())
            .unwrap()
            .mesh;
        let truth = limit_face_varying_exact(&mesh, scheme).unwrap().unwrap();
        let (offsets, _) = mesh.face_lists();
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let rates = (0..mesh.num_edges())
            .map(|_| 1 + rng.below(6) as u32)
            .collect();
        let t = tessellate_rates(&eval, &EdgeRates::from_rates(rates)).unwrap();
        let s = &t.surface;
        let mut checked = 0;
        for c in 0..s.face_indices().len() {
            let (f, uv) = t.corner_param(c);
            let n = mesh.face_size(FaceId(f));
            let domain = Domain::of(scheme, n);
            let Some(k) = (0..n).find(|&k| domain.corner(k) == uv) else {
                continue;
            };
            let want = truth.corner(offsets[f as usize] as usize + k);
            let got = Vec2::from(s.uvs()[s.uv_indices()[c] as usize]);
            assert!(
                (got - want).abs().max_element() < 1e-5,
                "{rel} corner {c}: {got} {want}"
            );
            checked += 1;
        }
        assert!(
            checked >= mesh.face_lists().1.len(),
            "{rel}: {checked} corners"
        );
    }
}

#[test]
fn uvs_at_uniform_rates_are_the_uniform_uvs_in_each_corners_face() {
    // Loop's units at rate 2^d are not its lattice (a fan, or an inner triangle of its own).
    for (rel, scheme) in CAGES.into_iter().filter(|c| c.1 == Scheme::CatmullClark) {
        let mesh = read_cage(fixtures().join(rel), &CageOptions::default())
            .unwrap()
            .mesh;
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        for d in 1..=3u8 {
            let t = tessellate_rates(&eval, &EdgeRates::uniform(&mesh, 1 << d)).unwrap();
            let uniform = subdiv_slate::tessellate(&mesh, d).unwrap();
            let per_face = uniform_corners(&mesh, &uniform, d);
            let all: usize = per_face.iter().map(Vec::len).sum();
            assert_eq!(all, uniform.face_indices().len(), "{rel}");
            let s = &t.surface;
            assert_eq!(s.uv_indices().len(), s.face_indices().len(), "{rel}");
            let mut worst = 0.0f32;
            for (c, &v) in s.face_indices().iter().enumerate() {
                let (f, _) = t.corner_param(c);
                let p = s.positions()[v as usize];
                let near = per_face[f as usize]
                    .iter()
                    .copied()
                    .min_by(|a, b| dist(a.0, p).total_cmp(&dist(b.0, p)))
                    .unwrap();
                assert!(
                    dist(near.0, p) < 1e-4,
                    "{rel} depth {d}: corner {c} off the lattice"
                );
                let got = s.uvs()[s.uv_indices()[c] as usize];
                let e = (got[0] - near.1[0]).abs().max((got[1] - near.1[1]).abs());
                worst = worst.max(e);
            }
            // grid_seam's semi-sharp crease: the evaluator's exact limit against the level-d
            // values, which have not converged there.
            let tolerance = if rel.contains("grid_seam") {
                2e-2
            } else {
                1e-5
            };
            assert!(worst < tolerance, "{rel} depth {d}: UVs differ by {worst}");
        }
    }
}

#[test]
fn a_face_varying_primvar_follows_each_corners_face() {
    for (rel, scheme) in CAGES {
        let mut soup = subdiv_mesh::read_obj_soup(fixtures().join(rel)).unwrap();
        soup.primvars = vec![Primvar {
            name: "st".into(),
            interpolation: PrimvarInterpolation::FaceVarying,
            width: 2,
            values: soup.uvs.iter().flat_map(|t| t.to_array()).collect(),
            indices: soup.uv_indices.iter().map(|&i| i as u32).collect(),
        }];
        soup.split_nonmanifold().unwrap();
        let mesh = Mesh::from_soup(&soup).unwrap();
        let eval = Evaluator::new(&mesh, scheme).unwrap();
        let rates: Vec<u32> = (0..mesh.num_edges() as u32).map(|e| 4 + e % 3).collect();
        let mut t = tessellate_rates(&eval, &EdgeRates::from_rates(rates)).unwrap();
        tessellation_primvars(&mesh, scheme, &mut t).unwrap();
        let s = &t.surface;
        // The three corners of a triangle name one face, and its UVs do not jump a seam (the
        // cube's faces span a quarter in its cross unwrap, at rates 4 to 6 a triangle less
        // than 0.1; the two sides of a seam edge lie a quarter apart or more).
        for (k, tri) in s.face_indices().chunks(3).enumerate() {
            let faces = [0, 1, 2].map(|i| t.corner_param(3 * k + i).0);
            assert!(
                faces[0] == faces[1] && faces[1] == faces[2],
                "{rel} triangle {k}: {faces:?}"
            );
            let uv = [0, 1, 2].map(|i| Vec2::from(s.uvs()[s.uv_indices()[3 * k + i] as usize]));
            let longest = (0..3)
                .map(|i| uv[i].distance(uv[(i + 1) % 3]))
                .fold(0.0, f32::max);
            if rel.contains("cube_uv") {
                assert!(longest < 0.15, "{rel} triangle {k} {tri:?}: UVs {uv:?}");
            }
        }
        let st = s.channel("st").unwrap();
        for c in 0..s.face_indices().len() {
            let uv = s.uvs()[s.uv_indices()[c] as usize];
            assert_eq!(st.at_corner(c, s.face_indices()), uv, "{rel} corner {c}");
        }
    }
}
