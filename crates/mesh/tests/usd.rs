//! USD input against the truth: every fixture stage (text, binary crate, usdz archive) gives the
//! cage of the OBJ that Pixar's USD library made from it (`fixtures/usd/make_fixtures.py`), and
//! bad input gets a typed error naming file, prim and attribute.

use std::path::PathBuf;

use subdiv_mesh::{
    BoundaryInterpolation, CageError, CageOptions, FaceVaryingLinear, Mesh, TriangleSubdivision,
    UsdError, UsdReadOptions, UsdScheme, read_cage, read_obj, read_usd,
};

fn fixture(name: &str) -> PathBuf {
    subdiv_test_support::fixture("usd").join(name)
}

fn usd(name: &str, prim: Option<&str>) -> Result<subdiv_mesh::UsdMesh, UsdError> {
    read_usd(
        fixture(name),
        &UsdReadOptions {
            prim: prim.map(str::to_string),
            ..Default::default()
        },
    )
}

/// Same topology, positions (bit for bit), tags, options and groups.
fn assert_same_cage(a: &Mesh, b: &Mesh, what: &str) {
    assert_eq!(a.num_vertices(), b.num_vertices(), "{what}");
    assert_eq!(a.num_faces(), b.num_faces(), "{what}");
    for f in a.faces() {
        assert_eq!(a.face_vertices(f), b.face_vertices(f), "{what}: face {f:?}");
    }
    for (i, (p, q)) in a.positions().iter().zip(b.positions()).enumerate() {
        assert_eq!(
            p.to_array().map(f32::to_bits),
            q.to_array().map(f32::to_bits),
            "{what}: vertex {i}: {p} vs {q}"
        );
    }
    assert_eq!(a.edge_sharpnesses(), b.edge_sharpnesses(), "{what}");
    assert_eq!(a.vertex_sharpnesses(), b.vertex_sharpnesses(), "{what}");
    assert_eq!(a.holes(), b.holes(), "{what}");
    assert_eq!(a.options(), b.options(), "{what}");
    assert_eq!(a.groups(), b.groups(), "{what}");
    assert_eq!(a.face_groups(), b.face_groups(), "{what}");
}

#[test]
fn every_fixture_stage_is_the_cage_pixar_usd_reads() {
    // World-space points too: both compose the transforms in f64 and round once.
    for (file, obj) in [
        ("scene.usda", "scene.obj"),
        ("scene.usdc", "scene.obj"),
        ("open_lefthanded.usda", "open_lefthanded.obj"),
        ("open_lefthanded.usdz", "open_lefthanded.obj"),
        ("tetra_loop.usda", "tetra_loop.obj"),
    ] {
        let u = usd(file, None).unwrap_or_else(|e| panic!("{e}"));
        let o = read_obj(fixture(obj)).unwrap();
        assert_same_cage(&u.mesh, &o, file);
    }
}

#[test]
fn attributes_map_to_scheme_options_and_tags() {
    let s = usd("scene.usdc", None).unwrap();
    assert_eq!(s.prims, ["/World/Cube", "/World/Props/Holder/Grid"]);
    assert_eq!(s.scheme, UsdScheme::CatmullClark);
    // USD's defaults, not OBJ's: edge-and-corner boundaries, corners-plus-1 face-varying.
    assert_eq!(
        s.mesh.options().boundary,
        BoundaryInterpolation::EdgeAndCorner
    );
    assert_eq!(s.face_varying, FaceVaryingLinear::CornersPlus1);
    let p = usd("open_lefthanded.usdz", None).unwrap();
    assert_eq!(p.mesh.options().boundary, BoundaryInterpolation::EdgeOnly);
    assert_eq!(p.mesh.options().triangles, TriangleSubdivision::Smooth);
    assert_eq!(p.face_varying, FaceVaryingLinear::All);
    assert_eq!(p.mesh.holes().iter().filter(|h| **h).count(), 1);
    assert_eq!(
        usd("tetra_loop.usda", None).unwrap().scheme,
        UsdScheme::Loop
    );
}

#[test]
fn one_prim_by_path_and_typed_errors_for_other_paths() {
    let g = usd("scene.usda", Some("/World/Props/Holder/Grid")).unwrap();
    assert_eq!((g.mesh.num_vertices(), g.mesh.num_faces()), (16, 9));
    assert_eq!(g.mesh.groups(), ["/World/Props/Holder/Grid"]);
    let e = usd("scene.usda", Some("/World")).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, UsdError::NoSuchMesh { .. }), "{e:?}");
    assert!(
        msg.contains("prim /World: a Xform prim, not a Mesh") && msg.contains("/World/Cube"),
        "{msg}"
    );
    // The inactive mesh is not part of the stage's meshes.
    let e = usd("scene.usda", Some("/Hidden")).unwrap_err();
    assert!(
        e.to_string()
            .contains("meshes: /World/Cube, /World/Props/Holder/Grid"),
        "{e}"
    );
    // A prim is a USD notion.
    let obj = fixture("scene.obj");
    let e = read_cage(
        &obj,
        &CageOptions {
            prim: Some("/World/Cube".into()),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, CageError::PrimNotUsd { .. }), "{e:?}");
}

fn temp_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("subdiv-usd-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A one-mesh stage with the quad `0 1 2 3` and `extra` attribute lines.
fn quad_stage(name: &str, extra: &str) -> PathBuf {
    let p = temp_dir().join(name);
    std::fs::write(
        &p,
        format!(
            "#usda 1.0\ndef Mesh \"Quad\"\n{{\n    int[] faceVertexCounts = [4]\n    \
             int[] faceVertexIndices = [0, 1, 2, 3]\n    \
             point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n{extra}\n}}\n"
        ),
    )
    .unwrap();
    p
}

#[test]
fn bad_input_gets_errors_naming_file_prim_and_attribute() {
    let cases = [
        (
            "counts.usda",
            "    int[] faceVertexCounts = [3]",
            "/Quad: faceVertexIndices: 4 indices, but faceVertexCounts adds up to 3",
        ),
        (
            "overrun.usda",
            "    int[] faceVertexCounts = [5]",
            "/Quad: faceVertexCounts: face 0: count 5 runs past the 4 faceVertexIndices",
        ),
        (
            "token.usda",
            "    uniform token interpolateBoundary = \"sharp\"",
            "/Quad: interpolateBoundary: unsupported value 'sharp' (expected none, edgeOnly, edgeAndCorner)",
        ),
        (
            "creases.usda",
            "    int[] creaseIndices = [0, 1, 2]\n    int[] creaseLengths = [2]\n    float[] creaseSharpnesses = [1]",
            "/Quad: creaseIndices: 3 indices, but creaseLengths adds up to 2",
        ),
        (
            "sharpness.usda",
            "    int[] creaseIndices = [0, 1, 2]\n    int[] creaseLengths = [3]\n    float[] creaseSharpnesses = [1, 2, 3]",
            "/Quad: creaseSharpnesses: 3 values; expected one per crease (1) or one per crease edge (2)",
        ),
        (
            "corners.usda",
            "    int[] cornerIndices = [0, 1]\n    float[] cornerSharpnesses = [1]",
            "/Quad: cornerSharpnesses: 1 values for 2 cornerIndices",
        ),
        (
            "type.usda",
            "    float[] holeIndices = [0.5]",
            "/Quad: holeIndices: expected int[], found",
        ),
        (
            "index.usda",
            "    int[] faceVertexCounts = [4, 3]\n    int[] faceVertexIndices = [0, 1, 2, 3, 0, 2, 7]",
            "/Quad: faceVertexIndices: face 1: vertex index 7 is out of range (the mesh has 4 vertices)",
        ),
        (
            "hole.usda",
            "    int[] holeIndices = [3]",
            "/Quad: holeIndices: hole tag names face 3, but the mesh has 1 faces",
        ),
        (
            "edge.usda",
            "    int[] creaseIndices = [0, 2]\n    int[] creaseLengths = [2]\n    float[] creaseSharpnesses = [1]",
            "/Quad: creaseIndices: crease tag names edge 0-2, which is not an edge of the mesh",
        ),
        (
            "scheme.usda",
            "    uniform token subdivisionScheme = \"sqrt3\"",
            "/Quad: subdivisionScheme: unsupported value 'sqrt3'",
        ),
        (
            "singular.usda",
            "    float3 xformOp:scale = (1, 0, 1)\n    uniform token[] xformOpOrder = [\"xformOp:scale\"]",
            "/Quad: xformOpOrder: the local-to-world transform is singular",
        ),
    ];
    for (name, extra, want) in cases {
        let p = quad_stage(name, extra);
        let e = read_usd(&p, &UsdReadOptions::default()).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with(&p.display().to_string()), "{name}: {msg}");
        assert!(msg.contains(want), "{name}: {msg}\n  wanted: {want}");
    }
    let e = read_usd(temp_dir().join("missing.usda"), &UsdReadOptions::default()).unwrap_err();
    assert!(matches!(e, UsdError::Io { .. }), "{e:?}");
    let garbage = temp_dir().join("garbage.usdc");
    std::fs::write(&garbage, b"not a crate file at all").unwrap();
    let e = read_usd(&garbage, &UsdReadOptions::default()).unwrap_err();
    assert!(matches!(e, UsdError::Open { .. }), "{e:?}");
    let empty = temp_dir().join("empty.usda");
    std::fs::write(&empty, "#usda 1.0\ndef Xform \"World\"\n{\n}\n").unwrap();
    let e = read_usd(&empty, &UsdReadOptions::default()).unwrap_err();
    assert!(matches!(e, UsdError::NoMesh { .. }), "{e:?}");
}

#[test]
fn merged_prims_must_agree_on_options() {
    let p = temp_dir().join("mixed.usda");
    let quad = |name: &str, ib: &str| {
        format!(
            "def Mesh \"{name}\"\n{{\n    uniform token interpolateBoundary = \"{ib}\"\n    \
             int[] faceVertexCounts = [4]\n    int[] faceVertexIndices = [0, 1, 2, 3]\n    \
             point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n}}\n"
        )
    };
    let text = format!(
        "#usda 1.0\n{}{}",
        quad("A", "edgeOnly"),
        quad("B", "edgeAndCorner")
    );
    std::fs::write(&p, text).unwrap();
    let e = read_usd(&p, &UsdReadOptions::default()).unwrap_err();
    assert!(
        e.to_string()
            .contains("interpolateBoundary differs between /A (EdgeOnly) and /B (EdgeAndCorner)"),
        "{e}"
    );
    let b = read_usd(
        &p,
        &UsdReadOptions {
            prim: Some("/B".into()),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(
        b.mesh.options().boundary,
        BoundaryInterpolation::EdgeAndCorner
    );
}

/// The signed volume of a closed mesh: positive when its faces wind counter-clockwise seen from
/// outside.
fn signed_volume(m: &Mesh) -> f32 {
    let mut v = 0.0;
    for f in m.faces() {
        let p: Vec<_> = m.face_vertices(f).iter().map(|&x| m.position(x)).collect();
        for k in 1..p.len() - 1 {
            v += p[0].dot(p[k].cross(p[k + 1])) / 6.0;
        }
    }
    v
}

#[test]
fn left_handed_and_mirrored_meshes_wind_counter_clockwise_in_world_space() {
    let tetra = "    int[] faceVertexCounts = [3, 3, 3, 3]\n    \
                 int[] faceVertexIndices = [0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3]\n    \
                 point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]\n";
    let reversed = "    int[] faceVertexCounts = [3, 3, 3, 3]\n    \
                    int[] faceVertexIndices = [0, 1, 2, 0, 3, 1, 1, 3, 2, 2, 3, 0]\n    \
                    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]\n";
    let mirror = "    float3 xformOp:scale = (-2, 1, 1)\n    uniform token[] xformOpOrder = [\"xformOp:scale\"]\n";
    let left = "    uniform token orientation = \"leftHanded\"\n";
    for (name, body, scale) in [
        ("right.usda", tetra.to_string(), 1.0),
        ("left.usda", format!("{reversed}{left}"), 1.0),
        // A mirroring transform reverses the world-space winding: the reader reverses it back.
        ("mirrored.usda", format!("{tetra}{mirror}"), 2.0),
        (
            "left_mirrored.usda",
            format!("{reversed}{left}{mirror}"),
            2.0,
        ),
    ] {
        let p = temp_dir().join(name);
        std::fs::write(&p, format!("#usda 1.0\ndef Mesh \"T\"\n{{\n{body}}}\n")).unwrap();
        let m = read_usd(&p, &UsdReadOptions::default()).unwrap().mesh;
        let v = signed_volume(&m);
        assert!((v - scale / 6.0).abs() < 1e-6, "{name}: volume {v}");
    }
}

/// `scene.usdc` with some bytes replaced (offset, new value), written to a temporary file.
fn patched_scene(name: &str, patch: &[(usize, u8)]) -> PathBuf {
    let mut b = std::fs::read(fixture("scene.usdc")).unwrap();
    for &(at, v) in patch {
        b[at] = v;
    }
    let p = temp_dir().join(name);
    std::fs::write(&p, b).unwrap();
    p
}

/// Crate files (found by the fuzzer, `tests/tests/fuzz_usd.rs`) whose counts made the reader
/// allocate terabytes, which aborted the process; the vendored reader now bounds them by the
/// bytes the file holds, so each is a typed error naming the file.
#[test]
fn absurd_sizes_in_a_crate_file_are_errors_not_allocations() {
    // (file, what the error says)
    let mut files: Vec<(PathBuf, &str)> = [
        (
            "alloc_1.usdc",
            "Unable to read TOKENS section: Unable to read vec",
        ),
        (
            "alloc_110.usdc",
            "Unable to read SPECS section: Unable to read vec",
        ),
        (
            "alloc_172.usdc",
            "Unable to read PATHS section: Unable to read vec",
        ),
    ]
    .iter()
    .map(|&(n, want)| (fixture("fuzz").join(n), want))
    .collect();
    // `scene.usdc` with the element count of an int array (`faceVertexCounts`) made huge...
    files.push((
        patched_scene("alloc_ints.usdc", &[(457, 0xdb)]),
        "faceVertexCounts: failed to decode field \"default\" at /World/Cube.faceVertexCounts: Unable to read vec",
    ));
    // ... of another int array, ...
    files.push((
        patched_scene(
            "alloc_a.usdc",
            &[(337, 0xfd), (338, 0xff), (339, 0xff), (340, 0xff), (822, 0), (823, 0), (826, 0), (827, 0)],
        ),
        "creaseIndices: failed to decode field \"default\" at /World/Cube.creaseIndices: Unable to read vec",
    ));
    // ... of the path table ...
    files.push((
        patched_scene(
            "alloc_b.usdc",
            &[(237, 0x01), (455, 0xcf), (2171, 0x80), (2407, 0x2c)],
        ),
        "Unable to read PATHS section: Unable to read vec",
    ));
    // ... and of a token array (whose reading then panics on a token index out of range).
    files.push((
        patched_scene(
            "alloc_tokens.usdc",
            &[
                (228, 0xff),
                (232, 0x00),
                (852, 0x94),
                (983, 0x7f),
                (984, 0x00),
            ],
        ),
        "the USD reader failed while reading prim /World/Cube: index out of bounds",
    ));
    // A list op's element count (the references of /World/Cube) made huge: reserving it whole
    // overflowed the capacity (a panic) or, a little smaller, would abort. Now the elements are
    // read until one names a string that is not there (a panic, caught).
    files.push((
        patched_scene("alloc_references.usdc", &[(1808, 0x23)]),
        "the USD reader failed while reading prim /World/Cube: index out of bounds",
    ));
    for (p, want) in files {
        let e = read_usd(&p, &UsdReadOptions::default()).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with(&format!("{}: ", p.display())), "{msg}");
        assert!(msg.contains(want), "{msg}\n  wanted: {want}");
    }
}

/// A crate file (found by the fuzzer) with a property name holding a `}`: the reader's walk
/// up the path's ancestors never ended. Now it ends, and the file reads as far as it goes.
#[test]
fn a_path_with_a_stray_brace_has_ancestors_that_end() {
    let p = fixture("fuzz").join("hang_path_parent.usdc");
    let e = read_usd(&p, &UsdReadOptions::default()).unwrap_err();
    assert!(
        matches!(&e, UsdError::Invalid { prim, attr: "faceVertexIndices", .. } if prim == "/World/M0"),
        "{e:?}"
    );
}

/// A panic inside openusd (here an index out of range while it builds the paths of a crate
/// file whose path table was altered) is a typed error naming the file and the step.
#[test]
fn a_panic_in_the_reader_is_a_typed_error() {
    let p = patched_scene(
        "panics.usdc",
        &[(2105, 0xfe), (2106, 0xff), (2107, 0xff), (2108, 0x14)],
    );
    let e = read_usd(&p, &UsdReadOptions::default()).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, UsdError::ReaderPanic { .. }), "{e:?}");
    let want = format!(
        "{}: the USD reader failed while opening the stage: ",
        p.display()
    );
    assert!(msg.starts_with(&want), "{msg}");
    assert!(
        msg.contains("index out of bounds") && msg.contains("(at openusd"),
        "{msg}"
    );
    // The same through read_cage.
    let e = read_cage(&p, &CageOptions::default()).unwrap_err();
    assert!(
        matches!(e, CageError::Usd(UsdError::ReaderPanic { .. })),
        "{e:?}"
    );
}
