//! Primvars on the uniform tessellations (`subdiv_slate::tessellate_primvars`) against the
//! truth, every scheme:
//! - vertex primvars of widths 1 to 5 that are affine images of the positions: their limit is
//!   the same image of OpenSubdiv's limit positions (the reference files), since every limit
//!   mask's weights sum to one;
//! - face-varying primvars of widths 1 to 4 that are affine images of the texture
//!   coordinates, with the same indices and option: the same image of the surface's UVs, which
//!   agree with OpenSubdiv's `LimitFaceVarying` (`uv_slates.rs`, `osd_fvar.rs`);
//! - varying primvars (Catmull-Clark): the bilinear refinement of the cage's values, which is
//!   what OpenSubdiv's `InterpolateVarying` computes (the bilinear scheme's points, checked
//!   against OpenSubdiv in `reference.rs`);
//! - uniform primvars: one value over every face's descendants.

use glam::{DVec3, Vec3};
use subdiv_mesh::{FaceVarying, Mesh, PolygonSoup, Primvar, PrimvarInterpolation, read_obj};
use subdiv_rules::{Depth, LimitMesh, Scheme};
use subdiv_tests::{PointGrid, Reference, fixture_files, fixtures};

/// An affine map of `width` rows applied to a 3-vector.
fn affine(width: usize, p: DVec3) -> Vec<f64> {
    (0..width)
        .map(|r| {
            let r = r as f64;
            (0.5 + r) * p.x - (1.0 - 0.3 * r) * p.y + 0.25 * r * p.z + 0.1 * r - 0.7
        })
        .collect()
}

fn tessellate(mesh: &Mesh, scheme: Scheme, depth: Depth) -> LimitMesh {
    let mut t = match scheme {
        Scheme::CatmullClark => subdiv_slate::tessellate(mesh, depth),
        Scheme::Loop => subdiv_slate::tessellate_tri(mesh, depth),
        Scheme::Bilinear => subdiv_slate::tessellate_bilinear(mesh, depth),
    }
    .unwrap();
    subdiv_slate::tessellate_primvars(mesh, scheme, depth, &mut t).unwrap();
    t
}

/// The cage of `path` with a vertex primvar `w<width>` per width, the affine image of its
/// positions.
fn with_vertex_primvars(path: &std::path::Path, widths: &[usize]) -> Mesh {
    let mut soup = subdiv_mesh::read_obj_soup(path).unwrap();
    for &w in widths {
        let values = soup
            .positions
            .iter()
            .flat_map(|p| affine(w, p.as_dvec3()).into_iter().map(|x| x as f32))
            .collect();
        soup.primvars.push(Primvar {
            name: format!("w{w}"),
            interpolation: PrimvarInterpolation::Vertex,
            width: w,
            values,
            indices: (0..soup.positions.len() as u32).collect(),
        });
    }
    Mesh::from_soup(&soup).unwrap()
}

#[test]
fn vertex_primvars_take_opensubdivs_limit_masks() {
    let mut checked = 0;
    for file in fixture_files("reference/limit", "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        let (shape, lv) = name.rsplit_once(".L").unwrap();
        if lv != "2" {
            continue;
        }
        let cage = match shape.strip_prefix("bilinear_") {
            Some(rest) => format!("catmark_{rest}"),
            None => shape.to_string(),
        };
        let path = fixtures().join(format!("reference/shapes/{cage}.obj"));
        let reference = Reference::read(&file);
        let scheme = subdiv_tests::osd_compare::reference_scheme(&reference);
        let mesh = with_vertex_primvars(&path, &[1, 2, 3, 4, 5]);
        let t = tessellate(&mesh, scheme, 2);
        let (lo, hi) = mesh.bounds();
        let scale = (hi - lo).length() as f64;
        let grid = PointGrid::new(&reference.positions, 1e-3 * scale);
        for w in 1..=5 {
            let c = t.channel(&format!("w{w}")).unwrap();
            assert!(c.per_vertex() && c.width == w);
            for (i, p) in t.positions().iter().enumerate() {
                let (r, d) = grid.nearest(Vec3::from(*p).as_dvec3());
                assert!(
                    d < 1e-4 * scale,
                    "{name}: vertex {i} far from the reference"
                );
                let want = affine(w, reference.positions[r]);
                for (k, (&got, want)) in c.value(i).iter().zip(want).enumerate() {
                    let err = (f64::from(got) - want).abs();
                    assert!(
                        err < 2e-5 * scale.max(1.0),
                        "{name} w{w}[{k}] at {i}: {got} vs {want}"
                    );
                }
            }
        }
        checked += 1;
    }
    assert!(checked >= 40, "{checked}");
}

/// The UV cages of `fixtures/meshes/fvar` with face-varying primvars of widths 1 to 4, affine
/// images of the texture coordinates with the same indices.
#[test]
fn face_varying_primvars_follow_the_uv_rules() {
    let mut corners = 0;
    for shape in ["cube_uv", "grid_seam", "grid_seam_crease", "tri_seam"] {
        let base = read_obj(fixtures().join(format!("meshes/fvar/{shape}.obj"))).unwrap();
        let uv = base.uv().unwrap().clone();
        let schemes: &[Scheme] = if shape == "tri_seam" {
            &[Scheme::CatmullClark, Scheme::Loop, Scheme::Bilinear]
        } else {
            &[Scheme::CatmullClark, Scheme::Bilinear]
        };
        for option in subdiv_mesh::FVarLinearInterpolation::ALL {
            let mut mesh = base.clone();
            mesh.set_fvar_option(option);
            let mesh = with_face_varying(&mesh, &uv);
            for &scheme in schemes {
                for depth in [1, 3] {
                    let t = tessellate(&mesh, scheme, depth);
                    for w in 1..=4 {
                        let c = t.channel(&format!("f{w}")).unwrap();
                        assert!(!c.per_vertex());
                        for k in 0..t.face_indices().len() {
                            let st = t.uvs()[t.uv_indices()[k] as usize];
                            let want = affine(w, DVec3::new(st[0].into(), st[1].into(), 0.0));
                            for (&got, want) in c.at_corner(k, t.face_indices()).iter().zip(want) {
                                assert!(
                                    (f64::from(got) - want).abs() < 1e-5,
                                    "{shape} {option:?} {scheme:?} depth {depth} f{w} corner {k}: {got} vs {want}"
                                );
                            }
                            corners += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(corners > 100_000, "{corners}");
}

/// `mesh` with face-varying primvars `f1`..`f4`: affine images of `uv`, same indices.
fn with_face_varying(mesh: &Mesh, uv: &FaceVarying) -> Mesh {
    let mut soup = soup_of(mesh);
    for w in 1..=4 {
        soup.primvars.push(Primvar {
            name: format!("f{w}"),
            interpolation: PrimvarInterpolation::FaceVarying,
            width: w,
            values: uv
                .values
                .iter()
                .flat_map(|t| {
                    affine(w, DVec3::new(t.x.into(), t.y.into(), 0.0))
                        .into_iter()
                        .map(|x| x as f32)
                })
                .collect(),
            indices: uv.indices.clone(),
        });
    }
    Mesh::from_soup(&soup).unwrap()
}

/// The soup of a manifold mesh without tags (faces, positions, options, UVs).
fn soup_of(mesh: &Mesh) -> PolygonSoup {
    let (offsets, verts) = mesh.face_lists();
    let faces: Vec<Vec<u32>> = (0..mesh.num_faces())
        .map(|f| {
            verts[offsets[f] as usize..offsets[f + 1] as usize]
                .iter()
                .map(|v| v.0)
                .collect()
        })
        .collect();
    let mut soup = PolygonSoup::from_faces(mesh.positions().to_vec(), &faces);
    soup.options = mesh.options();
    if let Some(uv) = mesh.uv() {
        soup.uvs = uv.values.clone();
        soup.uv_indices = uv.indices.iter().map(|&i| i.into()).collect();
    }
    soup
}

#[test]
fn varying_primvars_are_the_bilinear_refinement_and_uniform_ones_constant_per_face() {
    let mesh = read_obj(fixtures().join("reference/shapes/catmark_nonquads.obj")).unwrap();
    let mut soup = soup_of(&mesh);
    soup.primvars.push(Primvar {
        name: "v3".into(),
        interpolation: PrimvarInterpolation::Varying,
        width: 3,
        values: mesh.positions().iter().flat_map(|p| p.to_array()).collect(),
        indices: (0..mesh.num_vertices() as u32).collect(),
    });
    soup.primvars.push(Primvar {
        name: "face".into(),
        interpolation: PrimvarInterpolation::Uniform,
        width: 1,
        values: (0..mesh.num_faces()).map(|f| f as f32).collect(),
        indices: (0..mesh.num_faces() as u32).collect(),
    });
    let mesh = Mesh::from_soup(&soup).unwrap();
    for depth in 1..=3 {
        let t = tessellate(&mesh, Scheme::CatmullClark, depth);
        // The level-`depth` vertices: limit positions (to find ours) and bilinear points.
        let limit = subdiv_rules::tessellate_uniform(&mesh, Scheme::CatmullClark, depth).unwrap();
        let bilinear = subdiv_rules::refine_uniform_levels(&mesh, Scheme::Bilinear, depth).unwrap();
        let lp: Vec<DVec3> = limit
            .positions()
            .iter()
            .map(|p| Vec3::from(*p).as_dvec3())
            .collect();
        let grid = PointGrid::new(&lp, 1e-3);
        let v3 = t.channel("v3").unwrap();
        for k in 0..t.face_indices().len() {
            let v = t.face_indices()[k] as usize;
            let (i, d) = grid.nearest(Vec3::from(t.positions()[v]).as_dvec3());
            assert!(d < 1e-4);
            let want = bilinear.positions()[i];
            let got = v3.at_corner(k, t.face_indices());
            assert!(
                (Vec3::from_slice(got) - want).abs().max_element() < 1e-5,
                "depth {depth} corner {k}: {got:?} vs {want}"
            );
        }
        let face = t.channel("face").unwrap();
        let per_face = 4usize.pow(u32::from(depth) - 1);
        let mut next = 0;
        for f in mesh.faces() {
            let n = mesh.face_size(f) * per_face;
            for q in next..next + n {
                for k in t.face_offsets()[q]..t.face_offsets()[q + 1] {
                    let got = face.at_corner(k as usize, t.face_indices());
                    assert_eq!(got, [f.0 as f32], "depth {depth} face {q}");
                }
            }
            next += n;
        }
    }
}
