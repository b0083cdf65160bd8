//! USD input and glTF/PLY output through the `subdiv` binary: the scheme a stage names, `--prim`,
//! the output format chosen by `-o`'s extension, and typed errors (never a panic).

mod common;

use common::{assert_fails, run, tmp};
use subdiv_test_support::fixtures;

fn usd(name: &str) -> String {
    fixtures().join("usd").join(name).display().to_string()
}

#[test]
fn tessellate_usd_to_gltf_and_ply() {
    // The stage says loop: no --scheme needed.
    let glb = tmp("tetra.glb");
    let (code, stdout, err) = run(&[
        "tessellate",
        &usd("tetra_loop.usda"),
        "--depth",
        "2",
        "-o",
        glb.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("(loop, depth 2)"), "{stdout}");
    let bytes = std::fs::read(&glb).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    assert!(String::from_utf8_lossy(&bytes).contains("\"_DEPTH\""));

    let ply = tmp("cube.ply");
    let (code, stdout, err) = run(&[
        "tessellate",
        &usd("scene.usdc"),
        "--prim",
        "/World/Cube",
        "--depth",
        "1",
        "-o",
        ply.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("(catmull-clark, depth 1)"), "{stdout}");
    let bytes = std::fs::read(&ply).unwrap();
    assert!(bytes.starts_with(b"ply\nformat binary_little_endian 1.0\n"));

    // Adaptive, with a camera: glTF JSON and its .bin.
    let gltf = tmp("scene.gltf");
    let (code, _, err) = run(&[
        "tessellate",
        &usd("open_lefthanded.usdz"),
        "--eye-relative",
        "0.5,0.5,2",
        "-o",
        gltf.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(gltf.with_extension("bin").exists());
    let text = std::fs::read_to_string(&gltf).unwrap();
    assert!(
        text.contains("\"NORMAL\"") && text.contains("\"_DEPTH\""),
        "{text}"
    );
}

#[test]
fn refine_usd_writes_doi_attribute() {
    let out = tmp("refined.glb");
    let (code, _, err) = run(&[
        "refine",
        &usd("tetra_loop.usda"),
        "--doi",
        "dihedral",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(String::from_utf8_lossy(&std::fs::read(&out).unwrap()).contains("\"_DOI\""));
}

/// `refine` carries the cage's UVs: the octahedron with a seam loop, refined
/// where the dihedral DoI says, writes `f v/vt` with both sides of the seam (more values than
/// points), glTF `TEXCOORD_0` and PLY `s t`, and warns about nothing.
#[test]
fn refine_carries_the_cages_uvs() {
    let cage = fixtures().join("meshes/fvar/tri_seam.obj");
    let cage_mesh = subdiv_mesh::read_obj(&cage).unwrap();
    for ext in ["obj", "glb", "ply"] {
        let out = tmp(&format!("refined_uv.{ext}"));
        let args = [
            "refine",
            cage.to_str().unwrap(),
            "--doi",
            "dihedral",
            "--threshold",
            "10",
            "-o",
            out.to_str().unwrap(),
        ];
        let (code, _, err) = run(&args);
        assert_eq!(code, 0, "{err}");
        assert!(!err.contains("UV"), "{err}");
        let bytes = std::fs::read(&out).unwrap();
        match ext {
            "obj" => {
                let m = subdiv_mesh::read_obj(&out).unwrap();
                assert!(m.num_faces() > cage_mesh.num_faces(), "refined");
                let fv = m.uv().expect("vt written");
                assert_eq!(fv.indices.len(), 3 * m.num_faces());
                assert!(fv.values.len() > m.num_vertices(), "a seam lost a side");
                // Refined values stay inside the cage's UV range.
                let (lo, hi) = cage_mesh.uv().unwrap().values.iter().fold(
                    (glam::Vec2::splat(f32::MAX), glam::Vec2::splat(f32::MIN)),
                    |(lo, hi), &t| (lo.min(t), hi.max(t)),
                );
                assert!(
                    fv.values
                        .iter()
                        .all(|&t| t.cmpge(lo).all() && t.cmple(hi).all())
                );
            }
            "glb" => assert!(String::from_utf8_lossy(&bytes).contains("\"TEXCOORD_0\"")),
            _ => assert!(String::from_utf8_lossy(&bytes).contains("property float s\n")),
        }
    }
}

#[test]
fn usd_and_output_errors_are_typed() {
    let o = tmp("x.glb");
    let o = o.to_str().unwrap();
    assert_fails(
        &[
            "tessellate",
            &usd("scene.usda"),
            "--prim",
            "/World",
            "--depth",
            "1",
            "-o",
            o,
        ],
        "scene.usda: prim /World: a Xform prim, not a Mesh (meshes: /World/Cube, /World/Props/Holder/Grid)",
    );
    let cube = fixtures().join("reference/shapes/catmark_cube.obj");
    assert_fails(
        &[
            "tessellate",
            cube.to_str().unwrap(),
            "--prim",
            "/A",
            "--depth",
            "1",
            "-o",
            o,
        ],
        "a prim (/A) can only be chosen in a USD file",
    );
    let stl = tmp("x.stl");
    assert_fails(
        &[
            "tessellate",
            cube.to_str().unwrap(),
            "--depth",
            "1",
            "-o",
            stl.to_str().unwrap(),
        ],
        "unknown output format",
    );
    // none (a polygon mesh) needs an explicit scheme.
    let polygons = tmp("none.usda");
    std::fs::write(
        &polygons,
        "#usda 1.0\ndef Mesh \"Q\"\n{\n    uniform token subdivisionScheme = \"none\"\n    \
         int[] faceVertexCounts = [4]\n    int[] faceVertexIndices = [0, 1, 2, 3]\n    \
         point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n}\n",
    )
    .unwrap();
    let b = polygons.to_str().unwrap();
    assert_fails(
        &["tessellate", b, "--depth", "1", "-o", o],
        "/Q: subdivisionScheme is none, a polygon mesh rather than a subdivision surface",
    );
    let (code, _, err) = run(&[
        "tessellate",
        b,
        "--scheme",
        "catmull-clark",
        "--depth",
        "1",
        "-o",
        o,
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, stdout, _) = run(&["info", b]);
    assert_eq!(code, 0);
    assert!(stdout.contains("subdivisionScheme: none"), "{stdout}");
}

/// `render` follows a stage naming Loop (uniform and adaptive), never drawing it as a
/// Catmull-Clark surface; `tessellate` adaptively too, the same surface as `--scheme loop`.
#[test]
fn render_and_tessellate_follow_a_loop_stage() {
    let png = tmp("tetra_loop.png");
    let png = png.to_str().unwrap();
    let stage = usd("tetra_loop.usda");
    for extra in [&["--depth", "1"][..], &["--pixel-error", "1"][..]] {
        let mut args = vec!["render", stage.as_str(), "--size", "64x48", "-o", png];
        args.extend_from_slice(extra);
        if let Some(o) = common::run_ok(&args) {
            let out = String::from_utf8_lossy(&o.stdout);
            assert!(
                out.contains("loop, depth 1") || out.contains("adaptive"),
                "{out}"
            );
        }
    }
    let (a, b) = (tmp("tetra_stage.obj"), tmp("tetra_named.obj"));
    for (out, scheme) in [(&a, None), (&b, Some("loop"))] {
        let mut args = vec![
            "tessellate",
            stage.as_str(),
            "--eye-relative",
            "0.4,0.3,2.5",
            "-o",
            out.to_str().unwrap(),
        ];
        if let Some(s) = scheme {
            args.extend(["--scheme", s]);
        }
        let (code, _, err) = run(&args);
        assert_eq!(code, 0, "{err}");
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

/// `bench tessellate` follows the stage's scheme (Loop on the triangular slates, its line says
/// so); so does `bench quality` (reference and configurations all Loop).
#[test]
fn bench_follows_or_refuses_the_stage_scheme() {
    let (code, out, err) = run(&[
        "bench",
        "tessellate",
        &usd("tetra_loop.usda"),
        "--depth",
        "2",
        "--runs",
        "1",
        "--threads",
        "1",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("scheme=loop"), "{out}");
    let stage = usd("tetra_loop.usda");
    let args = [
        "bench",
        "quality",
        &stage,
        "--size",
        "64x48",
        "--max-depth",
        "2",
        "--runs",
        "1",
    ];
    if let Some(o) = common::run_ok(&args) {
        let out = String::from_utf8_lossy(&o.stdout);
        for config in ["uniform-2", "curvature", "pixel-error-1"] {
            assert!(out.contains(config), "{out}");
        }
    }
}

/// A stage naming `subdivisionScheme = "bilinear"` is tessellated with the bilinear scheme (as
/// `--scheme bilinear` does for the same cage as OBJ), uniformly and adaptively.
#[test]
fn a_bilinear_stage_is_tessellated_bilinear() {
    let stage = tmp("bilinear_tri_quad.usda");
    std::fs::write(
        &stage,
        "#usda 1.0\ndef Mesh \"Tri\" {\n    int[] faceVertexCounts = [3, 4]\n    \
         int[] faceVertexIndices = [0, 1, 2, 1, 3, 4, 2]\n    \
         point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0.5), (2, 0, 1), (1.5, 1, 0)]\n    \
         uniform token subdivisionScheme = \"bilinear\"\n    \
         uniform token interpolateBoundary = \"edgeOnly\"\n}\n",
    )
    .unwrap();
    let obj = tmp("bilinear.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 0 1 0.5\nv 2 0 1\nv 1.5 1 0\nf 1 2 3\nf 2 4 5 3\n",
    )
    .unwrap();
    let (a, b) = (tmp("bilinear-usd.ply"), tmp("bilinear-obj.ply"));
    let (code, stdout, err) = run(&[
        "tessellate",
        stage.to_str().unwrap(),
        "--depth",
        "3",
        "-o",
        a.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("(bilinear, depth 3)"), "{stdout}");
    let (code, _, err) = run(&[
        "tessellate",
        obj.to_str().unwrap(),
        "--scheme",
        "bilinear",
        "--depth",
        "3",
        "-o",
        b.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap());
    // Adaptive too: the stage and the OBJ give the same frame.
    let (c, d) = (
        tmp("bilinear-usd-adaptive.ply"),
        tmp("bilinear-obj-adaptive.ply"),
    );
    for (input, out, scheme) in [(&stage, &c, None), (&obj, &d, Some("bilinear"))] {
        let mut args = vec![
            "tessellate",
            input.to_str().unwrap(),
            "--eye-relative",
            "0.8,0.5,2.2",
            "-o",
            out.to_str().unwrap(),
        ];
        if let Some(s) = scheme {
            args.extend(["--scheme", s]);
        }
        let (code, stdout, err) = run(&args);
        assert_eq!(code, 0, "{err}");
        assert!(stdout.contains("(adaptive, max depth"), "{stdout}");
    }
    assert!(std::fs::read(&c).unwrap() == std::fs::read(&d).unwrap());
}
