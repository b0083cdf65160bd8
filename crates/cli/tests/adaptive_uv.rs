//! UVs through adaptive `tessellate` (curvature and pixel-error modes) and the exports: the
//! cube's cross unwrap written as OBJ (re-read: every triangle corner has a `vt` inside the
//! unwrap, the unwrap's corners kept), glTF (`TEXCOORD_0`) and PLY (`s t`).

mod common;

use common::{run, tmp};
use subdiv_test_support::fixtures;

#[test]
fn adaptive_tessellation_writes_texture_coordinates() {
    let cube = fixtures().join("meshes/fvar/cube_uv.obj");
    let cube = cube.to_str().unwrap();
    for (mode, flags) in [
        (
            "curvature",
            vec!["--eye-relative", "0.8,0.5,2.2", "--max-depth", "4"],
        ),
        (
            "pixel-error",
            vec![
                "--eye-relative",
                "0.8,0.5,2.2",
                "--pixel-error",
                "1",
                "--max-depth",
                "4",
            ],
        ),
    ] {
        let out = tmp(&format!("cube_uv_{mode}.obj"));
        let mut args = vec!["tessellate", cube];
        args.extend(&flags);
        args.extend(["--stats", "-o", out.to_str().unwrap()]);
        let (code, stdout, err) = run(&args);
        assert_eq!(code, 0, "{mode}: {err}");
        let tris: usize = stdout
            .lines()
            .find_map(|l| l.strip_prefix("triangles: "))
            .unwrap()
            .parse()
            .unwrap();
        let m = subdiv_mesh::read_obj(&out).unwrap();
        assert_eq!(m.num_faces(), tris, "{mode}");
        let fv = m.uv().expect("texture coordinates written");
        assert_eq!(fv.indices.len(), 3 * tris);
        assert!(
            fv.values
                .iter()
                .all(|t| t.x >= 0.0 && t.x <= 1.0 && t.y >= 0.0 && t.y <= 1.0),
            "{mode}: a UV outside the unwrap"
        );
        assert!(fv.values.contains(&glam::Vec2::new(0.25, 0.0)), "{mode}");
        // A seam keeps both sides: more distinct values than points on the seams' vertices.
        assert!(fv.values.len() > m.num_vertices(), "{mode}");
        for ext in ["glb", "ply"] {
            let out = tmp(&format!("cube_uv_{mode}.{ext}"));
            let mut args = vec!["tessellate", cube];
            args.extend(&flags);
            args.extend(["-o", out.to_str().unwrap()]);
            let (code, _, err) = run(&args);
            assert_eq!(code, 0, "{mode} {ext}: {err}");
            let bytes = std::fs::read(&out).unwrap();
            let text = String::from_utf8_lossy(&bytes);
            let want = if ext == "glb" {
                "TEXCOORD_0"
            } else {
                "property float s"
            };
            assert!(text.contains(want), "{mode} {ext}");
        }
    }
}

/// A USD cage's `primvars:st` reach the output: the hand-written stage tessellates (uniform and
/// adaptive) to exactly the file its OBJ twin gives.
#[test]
fn usd_texture_coordinates_reach_the_output() {
    let usda = fixtures().join("usd/cube_uv.usda");
    let obj = fixtures().join("meshes/fvar/cube_uv.obj");
    for (what, flags) in [
        ("uniform", vec!["--depth", "3"]),
        (
            "adaptive",
            vec!["--eye-relative", "0.8,0.5,2.2", "--max-depth", "3"],
        ),
    ] {
        let mut files = Vec::new();
        for (name, input) in [("usd", &usda), ("obj", &obj)] {
            let out = tmp(&format!("cube_uv_{what}_{name}.obj"));
            let mut args = vec!["tessellate", input.to_str().unwrap()];
            args.extend(&flags);
            args.extend(["-o", out.to_str().unwrap()]);
            let (code, _, err) = run(&args);
            assert_eq!(code, 0, "{what} {name}: {err}");
            files.push(std::fs::read_to_string(&out).unwrap());
        }
        assert!(files[0].contains("\nvt "), "{what}");
        assert_eq!(files[0], files[1], "{what}: USD and OBJ outputs differ");
    }
}

/// Adaptive Loop keeps the cage's UVs: the octahedron with a seam loop,
/// tessellated from a camera, writes a `vt` on every triangle corner, inside the cage's UV
/// range, with both sides of the seam (more values than points), and the values of the
/// uniform Loop tessellation at the deepest depth drawn among them.
#[test]
fn adaptive_loop_writes_texture_coordinates() {
    let cage = fixtures().join("meshes/fvar/tri_seam.obj");
    let cage = cage.to_str().unwrap();
    let out = tmp("tri_seam_adaptive.obj");
    let (code, stdout, err) = run(&[
        "tessellate",
        cage,
        "--scheme",
        "loop",
        "--eye-relative",
        "0.3,0.4,2.5",
        "--max-depth",
        "3",
        "--stats",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let tris: usize = stdout
        .lines()
        .find_map(|l| l.strip_prefix("triangles: "))
        .unwrap()
        .parse()
        .unwrap();
    let m = subdiv_mesh::read_obj(&out).unwrap();
    assert_eq!(m.num_faces(), tris);
    let fv = m.uv().expect("texture coordinates written");
    assert_eq!(fv.indices.len(), 3 * tris);
    assert!(
        fv.values
            .iter()
            .all(|t| t.x >= 0.0 && t.x <= 1.0 && t.y >= -0.1 && t.y <= 1.0),
        "a UV outside the cage's range"
    );
    assert!(fv.values.len() > m.num_vertices(), "a seam lost a side");
    let uniform = tmp("tri_seam_uniform.obj");
    let (code, _, err) = run(&[
        "tessellate",
        cage,
        "--scheme",
        "loop",
        "--depth",
        "3",
        "-o",
        uniform.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let u = subdiv_mesh::read_obj(&uniform).unwrap();
    let uv = u.uv().unwrap();
    assert!(
        fv.values.iter().all(|v| uv.values.contains(v)),
        "a value not in the depth-3 uniform tessellation's"
    );
}
