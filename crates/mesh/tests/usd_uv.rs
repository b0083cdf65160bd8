//! USD texture coordinates (`primvars:st`): the hand-written `fixtures/usd/cube_uv.usda`
//! (indexed `faceVarying`, seams) reads as the UV channel of its OBJ twin; `vertex`/`varying`
//! values, unindexed values and left-handed winding map corner by corner; bad or unsupported
//! forms give typed errors naming file, prim and attribute.

use std::path::PathBuf;

use subdiv_mesh::{FVarLinearInterpolation, UsdReadOptions, read_obj, read_usd};
use subdiv_test_support::fixtures;

fn temp_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("subdiv-usd-uv-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A stage with `body` inside one `Mesh` prim named `Quad` (the quad `0 1 2 3` unless the body
/// says otherwise) and `more` after it.
fn stage(name: &str, body: &str, more: &str) -> PathBuf {
    let p = temp_dir().join(name);
    std::fs::write(
        &p,
        format!(
            "#usda 1.0\ndef Mesh \"Quad\"\n{{\n    int[] faceVertexCounts = [4]\n    \
             int[] faceVertexIndices = [0, 1, 2, 3]\n    \
             point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n{body}\n}}\n{more}"
        ),
    )
    .unwrap();
    p
}

/// The UV of every face corner of a mesh, in corner order.
fn corner_uvs(m: &subdiv_mesh::Mesh) -> Vec<[f32; 2]> {
    let fv = m.uv().expect("UVs");
    (0..fv.indices.len())
        .map(|c| fv.corner(c).to_array())
        .collect()
}

#[test]
fn cube_uv_stage_is_its_obj_twin() {
    let u = read_usd(
        fixtures().join("usd/cube_uv.usda"),
        &UsdReadOptions::default(),
    )
    .unwrap();
    let o = read_obj(fixtures().join("meshes/fvar/cube_uv.obj")).unwrap();
    assert_eq!(corner_uvs(&u.mesh), corner_uvs(&o));
    assert_eq!(u.mesh.options().fvar, FVarLinearInterpolation::CornersOnly);
    assert_eq!(u.mesh.options().fvar, o.options().fvar);
    // 14 distinct values: the seams are kept.
    assert_eq!(u.mesh.uv().unwrap().values.len(), 14);
}

#[test]
fn vertex_unindexed_and_left_handed_forms_map_corner_by_corner() {
    let st = "[(0, 0), (1, 0), (1, 1), (0, 1)]";
    // Per point, indexed or not: each corner its point's value.
    for (name, body) in [
        (
            "vertex.usda",
            format!("    texCoord2f[] primvars:st = {st} (\n        interpolation = \"vertex\"\n    )"),
        ),
        (
            "varying_indexed.usda",
            "    texCoord2f[] primvars:st = [(1, 1), (0, 0), (1, 0), (0, 1)] (\n        interpolation = \"varying\"\n    )\n    int[] primvars:st:indices = [1, 2, 0, 3]".to_string(),
        ),
        (
            "facevarying.usda",
            format!("    texCoord2f[] primvars:st = {st} (\n        interpolation = \"faceVarying\"\n    )"),
        ),
    ] {
        let m = read_usd(stage(name, &body, ""), &UsdReadOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .mesh;
        assert_eq!(
            corner_uvs(&m),
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            "{name}"
        );
        // USD's default face-varying option.
        assert_eq!(m.options().fvar, FVarLinearInterpolation::CornersPlus1, "{name}");
    }
    // Left-handed: the face is rewound (0 3 2 1) and its corners' values with it, so every
    // vertex keeps its value.
    let body = format!(
        "    uniform token orientation = \"leftHanded\"\n    \
         uniform token faceVaryingLinearInterpolation = \"all\"\n    \
         texCoord2f[] primvars:st = {st} (\n        interpolation = \"faceVarying\"\n    )"
    );
    let m = read_usd(stage("left.usda", &body, ""), &UsdReadOptions::default())
        .unwrap()
        .mesh;
    let f = m.faces().next().unwrap();
    let verts: Vec<u32> = m.face_vertices(f).iter().map(|v| v.0).collect();
    let want: Vec<[f32; 2]> = verts
        .iter()
        .map(|&v| [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]][v as usize])
        .collect();
    assert_eq!(corner_uvs(&m), want);
    assert_ne!(verts, vec![0, 1, 2, 3]);
    assert_eq!(m.options().fvar, FVarLinearInterpolation::All);
}

#[test]
fn bad_texture_coordinates_get_typed_errors() {
    let fv = "(\n        interpolation = \"faceVarying\"\n    )";
    let cases = [
        (
            "count.usda",
            format!("    texCoord2f[] primvars:st = [(0, 0), (1, 0)] {fv}"),
            "/Quad: primvars:st: 2 values for 4 face corners",
        ),
        (
            "indices.usda",
            format!(
                "    texCoord2f[] primvars:st = [(0, 0), (1, 0)] {fv}\n    int[] primvars:st:indices = [0, 1, 2, 1]"
            ),
            "/Quad: primvars:st:indices: index 2 is 2, outside the 2 values of primvars:st",
        ),
        (
            "index_count.usda",
            format!(
                "    texCoord2f[] primvars:st = [(0, 0), (1, 0)] {fv}\n    int[] primvars:st:indices = [0, 1]"
            ),
            "/Quad: primvars:st:indices: 2 indices for 4 face corners",
        ),
        (
            "uniform.usda",
            "    texCoord2f[] primvars:st = [(0, 0)] (\n        interpolation = \"uniform\"\n    )"
                .to_string(),
            "/Quad: primvars:st: interpolation 'uniform' is not supported",
        ),
        (
            "constant.usda",
            "    texCoord2f[] primvars:st = [(0, 0)]".to_string(),
            "/Quad: primvars:st: interpolation 'constant' is not supported",
        ),
        (
            "type.usda",
            format!("    float[] primvars:st = [0, 1, 2, 3] {fv}"),
            "/Quad: primvars:st: expected texCoord2f[], found",
        ),
        (
            "vertex_count.usda",
            "    texCoord2f[] primvars:st = [(0, 0)] (\n        interpolation = \"vertex\"\n    )"
                .to_string(),
            "/Quad: primvars:st: 1 values for 4 points",
        ),
        (
            "option.usda",
            format!(
                "    uniform token faceVaryingLinearInterpolation = \"sometimes\"\n    texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] {fv}"
            ),
            "/Quad: faceVaryingLinearInterpolation: unsupported value 'sometimes'",
        ),
    ];
    for (name, body, want) in cases {
        let p = stage(name, &body, "");
        let msg = read_usd(&p, &UsdReadOptions::default())
            .unwrap_err()
            .to_string();
        assert!(msg.starts_with(&p.display().to_string()), "{name}: {msg}");
        assert!(msg.contains(want), "{name}: {msg}\n  wanted: {want}");
    }
    // Two prims, one with UVs and one without: refused, naming both.
    let other = "def Mesh \"Other\"\n{\n    int[] faceVertexCounts = [3]\n    \
                 int[] faceVertexIndices = [0, 1, 2]\n    \
                 point3f[] points = [(3, 0, 0), (4, 0, 0), (3, 1, 0)]\n}\n";
    let body = format!("    texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] {fv}");
    let p = stage("mixed.usda", &body, other);
    let msg = read_usd(&p, &UsdReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("primvars:st") && msg.contains("/Quad") && msg.contains("/Other"),
        "{msg}"
    );
}
