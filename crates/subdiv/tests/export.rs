//! glTF and PLY output re-read by independent readers (the `gltf` crate, which also validates
//! the document, and `ply-rs-bw`): every accessor's count, type and bounds (min/max), and every
//! value, against what was written — for uniform, adaptive and DoI-refined surfaces, with and
//! without texture coordinates.

use std::path::{Path, PathBuf};

use subdiv::doi::DoiKind;
use subdiv::mesh::{Camera, glam::Vec3, read_obj};
use subdiv::rules::Scheme;
use subdiv::{
    DoiOptions, DoiSetup, DynamicSubdivision, LimitMesh, OutputFormat, VertexScalar, uniform_limit,
    write_surface,
};
use subdiv_test_support::{fixture, shape};

fn out_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("subdiv-export-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Uniform (creases: one-sided normals), adaptive (per-vertex depths), DoI-refined (per-vertex
/// DoI) surfaces, and one with texture coordinates.
fn surfaces() -> Vec<(&'static str, LimitMesh)> {
    let cube = read_obj(shape("catmark_single_crease.obj")).unwrap();
    let mut uniform = uniform_limit(&cube, Scheme::CatmullClark, 2).unwrap();
    let depths = vec![2.0; uniform.num_vertices()];
    uniform.set_scalar(VertexScalar::Depth, depths).unwrap();
    assert!(
        uniform.split_sided(true).num_vertices() > uniform.num_vertices(),
        "crease corners get vertices of their own"
    );

    let pawn = read_obj(shape("catmark_pawn.obj")).unwrap();
    let (lo, hi) = pawn.bounds();
    let mut node = DynamicSubdivision::new(pawn, subdiv::depth::DepthParams::default()).unwrap();
    // Close to the pawn: near patches deep, far ones shallow.
    let camera = Camera::eye_relative(lo, hi, Vec3::new(0.3, -0.9, 0.6), 45.0, 640, 480);
    let g = node.update(&camera, None).unwrap();
    let adaptive = g.surface().referenced_only();
    let (dmin, dmax) = min_max(adaptive.scalar().unwrap().1);
    assert!(
        dmin < dmax,
        "the adaptive frame mixes depths: {dmin}..{dmax}"
    );

    let tetra = read_obj(shape("loop_tetrahedron.obj")).unwrap();
    let setup = DoiSetup::new(tetra, &DoiOptions::new(DoiKind::Dihedral)).unwrap();
    let r = setup.run(camera).unwrap();
    let refined = setup.refined_surface(&r, &camera).unwrap();

    let mut textured = uniform.split_sided(false);
    let uvs = textured
        .positions()
        .iter()
        .map(|p| [p[0], p[1] * 0.5])
        .collect();
    let corners = textured.face_indices().to_vec();
    textured.set_uvs(uvs, corners).unwrap();
    textured.clear_scalar();
    vec![
        ("uniform", uniform),
        ("adaptive", adaptive),
        ("refined", refined),
        ("textured", textured),
    ]
}

fn min_max(v: &[f32]) -> (f32, f32) {
    v.iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// The per-component bounds of `data`.
fn bounds<const N: usize>(data: &[[f32; N]]) -> (Vec<f32>, Vec<f32>) {
    let mut lo = vec![f32::INFINITY; N];
    let mut hi = vec![f32::NEG_INFINITY; N];
    for v in data {
        for k in 0..N {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    (lo, hi)
}

/// An accessor's `min` or `max` (JSON numbers written as the shortest decimal of the `f32`,
/// so they read back as the same `f32`).
fn json_vec(v: Option<gltf::json::Value>) -> Vec<f32> {
    v.expect("bounds written")
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect()
}

/// Checks one accessor: count, dimensions, and min/max equal to the data's.
fn check_accessor<const N: usize>(a: &gltf::Accessor, data: &[[f32; N]], what: &str) {
    assert_eq!(a.count(), data.len(), "{what}");
    assert_eq!(a.dimensions().multiplicity(), N, "{what}");
    assert_eq!(a.data_type(), gltf::accessor::DataType::F32, "{what}");
    let (lo, hi) = bounds(data);
    assert_eq!(json_vec(a.min()), lo, "{what}: min");
    assert_eq!(json_vec(a.max()), hi, "{what}: max");
}

/// The texture coordinates of a surface split with its UVs, one per vertex.
fn vertex_uvs(s: &LimitMesh) -> Option<Vec<[f32; 2]>> {
    (!s.uv_indices().is_empty()).then(|| s.uvs().to_vec())
}

/// Checks the glTF file written for `limit` against its split form.
fn check_gltf(path: &Path, limit: &LimitMesh, what: &str) {
    let s = &limit.split_sided(true);
    // `open` validates the document (indices, byte ranges, required bounds).
    let doc = gltf::Gltf::open(path).unwrap_or_else(|e| panic!("{what}: {e}"));
    let buffers: Vec<Vec<u8>> = doc
        .buffers()
        .map(|b| match b.source() {
            gltf::buffer::Source::Bin => doc.blob.clone().expect("GLB BIN chunk"),
            gltf::buffer::Source::Uri(u) => std::fs::read(path.with_file_name(u)).unwrap(),
        })
        .collect();
    assert_eq!(doc.meshes().count(), 1, "{what}");
    let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
    assert_eq!(prim.mode(), gltf::mesh::Mode::Triangles, "{what}");
    let reader = prim.reader(|b| Some(&buffers[b.index()][..]));
    let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    assert_eq!(pos, s.positions(), "{what}");
    let nrm: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
    assert_eq!(nrm, s.normals(), "{what}");
    let idx: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
    assert_eq!(idx, s.face_indices(), "{what}");
    let uv = reader
        .read_tex_coords(0)
        .map(|t| t.into_f32().collect::<Vec<_>>());
    assert_eq!(uv, vertex_uvs(s), "{what}");
    let ia = prim.indices().unwrap();
    assert_eq!(ia.count(), s.face_indices().len(), "{what}");
    let (lo, hi) = (
        s.face_indices().iter().min().unwrap(),
        s.face_indices().iter().max().unwrap(),
    );
    let index_bound = |v: Option<gltf::json::Value>| v.unwrap()[0].as_u64().unwrap();
    assert_eq!(index_bound(ia.min()), u64::from(*lo), "{what}");
    assert_eq!(index_bound(ia.max()), u64::from(*hi), "{what}");
    let mut custom = Vec::new();
    for (semantic, a) in prim.attributes() {
        match semantic {
            gltf::Semantic::Positions => check_accessor(&a, s.positions(), what),
            gltf::Semantic::Normals => check_accessor(&a, s.normals(), what),
            gltf::Semantic::TexCoords(0) => check_accessor(&a, s.uvs(), what),
            gltf::Semantic::Extras(name) => {
                let values: Vec<f32> =
                    gltf::accessor::Iter::<f32>::new(a.clone(), |b| Some(&buffers[b.index()][..]))
                        .unwrap()
                        .collect();
                let one: Vec<[f32; 1]> = values.iter().map(|&v| [v]).collect();
                check_accessor(&a, &one, what);
                custom.push((format!("_{name}"), values));
            }
            other => panic!("{what}: unexpected attribute {other:?}"),
        }
    }
    let want: Vec<(String, Vec<f32>)> = s
        .scalar()
        .iter()
        .map(|(k, v)| (k.gltf_attribute().to_string(), v.to_vec()))
        .collect();
    assert_eq!(custom, want, "{what}");
}

/// Checks the PLY file written for `limit` against its split form.
fn check_ply(path: &Path, limit: &LimitMesh, what: &str) {
    let s = &limit.split_sided(true);
    use ply_rs_bw::ply::{DefaultElement, Encoding, Property};
    let mut f = std::fs::File::open(path).unwrap();
    let ply = ply_rs_bw::parser::Parser::<DefaultElement>::new()
        .read_ply(&mut f)
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(
        matches!(ply.header.encoding, Encoding::BinaryLittleEndian),
        "{what}"
    );
    let float = |e: &DefaultElement, k: &str| match e.get(k) {
        Some(Property::Float(x)) => *x,
        other => panic!("{what}: property {k}: {other:?}"),
    };
    let verts = &ply.payload["vertex"];
    assert_eq!(verts.len(), s.num_vertices(), "{what}");
    for (i, v) in verts.iter().enumerate() {
        assert_eq!(
            [float(v, "x"), float(v, "y"), float(v, "z")],
            s.positions()[i],
            "{what}"
        );
        assert_eq!(
            [float(v, "nx"), float(v, "ny"), float(v, "nz")],
            s.normals()[i],
            "{what}"
        );
        if let Some(uv) = vertex_uvs(s) {
            assert_eq!([float(v, "s"), float(v, "t")], uv[i], "{what}");
        }
        if let Some((k, values)) = s.scalar() {
            assert_eq!(float(v, k.ply_property()), values[i], "{what}");
        }
    }
    let faces = &ply.payload["face"];
    let idx: Vec<u32> = faces
        .iter()
        .flat_map(|f| match f.get("vertex_indices") {
            Some(Property::ListUInt(l)) => l.clone(),
            other => panic!("{what}: {other:?}"),
        })
        .collect();
    assert_eq!(faces.len() * 3, idx.len(), "{what}: triangles only");
    assert_eq!(idx, s.face_indices(), "{what}");
}

#[test]
fn gltf_and_ply_files_reread_exactly() {
    let dir = out_dir();
    for (name, s) in surfaces() {
        for ext in ["glb", "gltf", "ply"] {
            let path = dir.join(format!("{name}.{ext}"));
            write_surface(&path, &s).unwrap();
            let what = format!("{name}.{ext}");
            match OutputFormat::from_path(&path).unwrap() {
                OutputFormat::Ply => check_ply(&path, &s, &what),
                _ => check_gltf(&path, &s, &what),
            }
        }
    }
}

#[test]
fn output_format_follows_the_extension() {
    let dir = out_dir();
    let cube = read_obj(shape("catmark_cube.obj")).unwrap();
    let t = uniform_limit(&cube, Scheme::CatmullClark, 1).unwrap();
    for (ext, format) in [
        ("obj", OutputFormat::Obj),
        ("GLB", OutputFormat::Glb),
        ("gltf", OutputFormat::Gltf),
        ("ply", OutputFormat::Ply),
    ] {
        let p = dir.join(format!("cube.{ext}"));
        assert_eq!(write_surface(&p, &t).unwrap(), format);
        assert!(p.exists());
    }
    // OBJ keeps the polygons; glTF and PLY hold their triangles.
    assert_eq!(read_obj(dir.join("cube.obj")).unwrap().num_faces(), 24);
    assert!(dir.join("cube.bin").exists(), "the .gltf data beside it");
    let e = write_surface(dir.join("cube.stl"), &t).unwrap_err();
    assert!(e.to_string().contains("unknown output format"), "{e}");
    // A surface with an index out of range cannot be made; one without faces is not written.
    let e = LimitMesh::from_triangles(vec![[0.0; 3]; 3], vec![[0.0, 0.0, 1.0]; 3], vec![0, 1, 3])
        .unwrap_err();
    assert!(
        e.to_string().ends_with("vertex index 3 for 3 values"),
        "{e}"
    );
    let e = write_surface(dir.join("bad.glb"), &LimitMesh::default()).unwrap_err();
    assert!(
        e.to_string().ends_with("bad.glb: no triangles to write"),
        "{e}"
    );
}

/// A cage with UVs (`vt`, a cube's cross unwrap with seams): the export gives every vertex the
/// UV of each face corner it stands for, splitting vertices on seams, and every triangle corner
/// keeps the position and the UV of its face corner in the tessellation.
#[test]
fn uvs_of_a_tessellated_cage_reach_the_export() {
    let path = fixture("meshes/fvar/cube_uv.obj");
    let cube = read_obj(path).unwrap();
    let mut t = uniform_limit(&cube, Scheme::CatmullClark, 2).unwrap();
    assert_eq!(
        t.uv_indices().len(),
        t.face_indices().len(),
        "UVs per corner"
    );
    t.set_scalar(VertexScalar::Depth, vec![2.0; t.num_vertices()])
        .unwrap();
    let s = t.split_sided(true);
    let uvs = vertex_uvs(&s).expect("the export carries the UVs");
    assert_eq!(uvs.len(), s.num_vertices());
    assert!(
        s.num_vertices() > t.num_vertices(),
        "seams split vertices: {} -> {}",
        t.num_vertices(),
        s.num_vertices()
    );
    s.check().unwrap();
    // Walk the faces as the export fans them and compare corner by corner.
    let mut tri = s.face_indices().chunks(3);
    for f in 0..t.num_faces() {
        let c: Vec<usize> = (t.face_offsets()[f]..t.face_offsets()[f + 1])
            .map(|c| c as usize)
            .collect();
        for k in 1..c.len() - 1 {
            let out = tri.next().expect("one triangle per fan step");
            for (&o, &corner) in out.iter().zip(&[c[0], c[k], c[k + 1]]) {
                let v = t.face_indices()[corner] as usize;
                assert_eq!(s.positions()[o as usize], t.positions()[v]);
                assert_eq!(uvs[o as usize], t.uvs()[t.uv_indices()[corner] as usize]);
            }
        }
    }
    assert!(tri.next().is_none());
    // And the file: a .glb re-read by the gltf crate holds TEXCOORD_0 as exported.
    let glb = out_dir().join("cube_uv.glb");
    write_surface(&glb, &t).unwrap();
    check_gltf(&glb, &t, "cube_uv.glb");
}

/// A cage with UVs refined where a DoI says (`subdiv refine`): the export carries the refined
/// mesh's UVs, every triangle corner the value of its face corner, vertices split at the seam;
/// the `.glb` re-read by the `gltf` crate holds `TEXCOORD_0`, one per vertex.
#[test]
fn uvs_of_a_refined_cage_reach_the_export() {
    let path = fixture("meshes/fvar/tri_seam.obj");
    let cage = read_obj(path).unwrap();
    let (lo, hi) = cage.bounds();
    let camera = Camera::eye_relative(lo, hi, Vec3::new(0.3, 0.4, 2.5), 45.0, 640, 480);
    let mut o = DoiOptions::new(DoiKind::ViewAngle);
    o.steps = 3;
    let setup = DoiSetup::new(cage, &o).unwrap();
    let r = setup.run(camera).unwrap();
    let m = &r.mesh.mesh;
    let fv = m.uv().expect("the refined mesh carries the UVs");
    let limit = setup.refined_surface(&r, &camera).unwrap();
    assert!(r.mesh.green.num_green_faces() > 0, "a partial refinement");
    assert_eq!(limit.uv_indices(), fv.indices);
    let s = limit.split_sided(true);
    let uvs = vertex_uvs(&s).expect("the export carries the UVs");
    assert_eq!(uvs.len(), s.num_vertices());
    // At least one vertex per distinct (vertex, value) pair: the seam splits vertices.
    let mut pairs: Vec<(u32, u32)> = limit
        .face_indices()
        .iter()
        .zip(limit.uv_indices())
        .map(|(&v, &t)| (v, t))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    assert!(pairs.len() > m.num_vertices());
    assert!(s.num_vertices() >= pairs.len());
    for (c, &o) in s.face_indices().iter().enumerate() {
        let (v, t) = (limit.face_indices()[c], limit.uv_indices()[c]);
        assert_eq!(s.positions()[o as usize], limit.positions()[v as usize]);
        assert_eq!(uvs[o as usize], limit.uvs()[t as usize]);
    }
    let glb = out_dir().join("tri_seam_refined.glb");
    write_surface(&glb, &limit).unwrap();
    check_gltf(&glb, &limit, "tri_seam_refined.glb");
}

/// A stage's colours, second UV set and other primvars reach the files: glTF `COLOR_0`,
/// `TEXCOORD_1` (after `st`'s `TEXCOORD_0`) and `_NAME`; PLY `red green blue`, `NAME` or
/// `NAME_k`; OBJ vertex colours. Every value is the split surface's.
#[test]
fn primvars_reach_gltf_ply_and_obj() {
    let stage = out_dir().join("primvars.usda");
    std::fs::write(
        &stage,
        r#"#usda 1.0
def Mesh "Q" {
    int[] faceVertexCounts = [4, 4]
    int[] faceVertexIndices = [0, 1, 4, 3, 1, 2, 5, 4]
    point3f[] points = [(0, 0, 0), (1, 0, 0.5), (2, 0, 0), (0, 1, 0), (1, 1, 0.5), (2, 1, 0)]
    color3f[] primvars:displayColor = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (0, 1, 1), (1, 0, 1)] (
        interpolation = "vertex"
    )
    texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] (
        interpolation = "faceVarying"
    )
    int[] primvars:st:indices = [0, 1, 2, 3, 0, 1, 2, 3]
    texCoord2f[] primvars:st1 = [(0, 0), (0.5, 0), (1, 0), (0, 1), (0.5, 1), (1, 1)] (
        interpolation = "vertex"
    )
    float[] primvars:opacity = [0.25, 0.75] (
        interpolation = "uniform"
    )
}
"#,
    )
    .unwrap();
    let cage = subdiv::mesh::read_usd(&stage, &Default::default())
        .unwrap()
        .mesh;
    let limit = uniform_limit(&cage, Scheme::CatmullClark, 2).unwrap();
    let names: Vec<&str> = limit.channels().iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["displayColor", "st1", "opacity"]);
    let s = limit.split_sided(true);
    let channel = |name: &str| s.channel(name).unwrap();
    let dir = out_dir();

    let glb = dir.join("primvars.glb");
    write_surface(&glb, &limit).unwrap();
    let doc = gltf::Gltf::open(&glb).unwrap();
    let blob = doc.blob.clone().unwrap();
    let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
    let reader = prim.reader(|_| Some(&blob[..]));
    let colours: Vec<[f32; 3]> = reader.read_colors(0).unwrap().into_rgb_f32().collect();
    let want: Vec<[f32; 3]> = channel("displayColor")
        .values
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    assert_eq!(colours, want);
    let st1: Vec<[f32; 2]> = reader.read_tex_coords(1).unwrap().into_f32().collect();
    let want: Vec<[f32; 2]> = channel("st1")
        .values
        .chunks(2)
        .map(|c| [c[0], c[1]])
        .collect();
    assert_eq!(st1, want);
    assert!(reader.read_tex_coords(0).is_some(), "st is TEXCOORD_0");
    let opacity = prim
        .attributes()
        .find(|(sem, _)| *sem == gltf::Semantic::Extras("OPACITY".into()))
        .map(|(_, a)| {
            gltf::accessor::Iter::<f32>::new(a, |_| Some(&blob[..]))
                .unwrap()
                .collect::<Vec<f32>>()
        })
        .expect("_OPACITY");
    assert_eq!(opacity, channel("opacity").values);
    assert!(opacity.contains(&0.25) && opacity.contains(&0.75));

    let ply = dir.join("primvars.ply");
    write_surface(&ply, &limit).unwrap();
    use ply_rs_bw::ply::{DefaultElement, Property};
    let mut f = std::fs::File::open(&ply).unwrap();
    let p = ply_rs_bw::parser::Parser::<DefaultElement>::new()
        .read_ply(&mut f)
        .unwrap();
    let float = |e: &DefaultElement, k: &str| match e.get(k) {
        Some(Property::Float(x)) => *x,
        other => panic!("property {k}: {other:?}"),
    };
    for (i, v) in p.payload["vertex"].iter().enumerate() {
        let rgb = [float(v, "red"), float(v, "green"), float(v, "blue")];
        assert_eq!(rgb, channel("displayColor").value(i));
        assert_eq!(
            [float(v, "st1_0"), float(v, "st1_1")],
            channel("st1").value(i)
        );
        assert_eq!([float(v, "opacity")], channel("opacity").value(i));
    }

    let obj = dir.join("primvars.obj");
    write_surface(&obj, &limit).unwrap();
    let back = subdiv::mesh::read_obj(&obj).unwrap();
    let c = back.primvar("displayColor").expect("OBJ vertex colours");
    assert_eq!(c.values, limit.channel("displayColor").unwrap().values);
}
