//! The `subdiv` binary end to end: outputs, and a clear `error: FILE:LINE: what` (never a panic)
//! for every kind of bad input.

mod common;

use common::{run, tmp};
use subdiv_test_support::fixtures;

const QUAD_HEAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

/// Bad cages: name, OBJ text, the message expected, and the line it names.
fn located_error_cases() -> Vec<(&'static str, String, &'static str, u32)> {
    vec![
        (
            "range",
            format!("{QUAD_HEAD}f 1 2 3 9\n"),
            "vertex index 8 is out of range",
            5,
        ),
        (
            "small",
            format!("{QUAD_HEAD}f 1 2\n"),
            "has 2 vertices; a face needs at least 3",
            5,
        ),
        (
            "repeat",
            format!("{QUAD_HEAD}f 1 2 2 3\n"),
            "more than once",
            5,
        ),
        (
            "nan",
            "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n".into(),
            "non-finite coordinate",
            2,
        ),
        (
            "inf",
            "v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n".into(),
            "non-finite coordinate",
            2,
        ),
        (
            "syntax",
            "v 0 0 0\nv 1 zero 0\n".into(),
            "invalid coordinate 'zero'",
            2,
        ),
        (
            "crease-edge",
            format!("{QUAD_HEAD}f 1 2 3 4\nt crease 2/1/0 0 2 1\n"),
            "not an edge of the mesh",
            6,
        ),
        (
            "crease-vertex",
            format!("{QUAD_HEAD}f 1 2 3 4\nt crease 2/1/0 0 7 1\n"),
            "names vertex 7",
            6,
        ),
        (
            "corner-vertex",
            format!("{QUAD_HEAD}f 1 2 3 4\nt corner 1/1/0 9 1\n"),
            "names vertex 9",
            6,
        ),
        (
            "hole-face",
            format!("{QUAD_HEAD}f 1 2 3 4\nt hole 1/0/0 3\n"),
            "names face 3",
            6,
        ),
        (
            "sharpness",
            format!("{QUAD_HEAD}f 1 2 3 4\nt crease 2/1/0 0 1 -2\n"),
            "invalid sharpness",
            6,
        ),
        (
            "tag-count",
            format!("{QUAD_HEAD}f 1 2 3 4\nt crease 2/1/0 0 1\n"),
            "announce 3 arguments",
            6,
        ),
        (
            "index-zero",
            format!("{QUAD_HEAD}f 0 1 2\n"),
            "face index 0 is invalid",
            5,
        ),
        (
            "texture-index-out-of-range",
            format!("{QUAD_HEAD}vt 0 0\nvt 1 0\nf 1/1 2/2 3/3 4/1\n"),
            "texture index 3 in '3/3' is out of range",
            7,
        ),
        (
            "texture-index-mixed",
            format!("{QUAD_HEAD}vt 0 0\nf 1/1 2/1 3 4/1\n"),
            "some corners of the face have a texture index",
            6,
        ),
        (
            "fvar-option",
            format!("{QUAD_HEAD}f 1 2 3 4\nt facevaryinginterpolateboundary 1/0/0 9\n"),
            "expected 0 (none) to 5 (all)",
            6,
        ),
    ]
}

#[test]
fn bad_inputs_give_located_errors() {
    let cases = located_error_cases();
    for (name, text, want, line) in &cases {
        let p = tmp(&format!("{name}.obj"));
        std::fs::write(&p, text).unwrap();
        let out = tmp(&format!("{name}.out.obj"));
        for args in [
            vec![
                "tessellate",
                p.to_str().unwrap(),
                "--depth",
                "1",
                "-o",
                out.to_str().unwrap(),
            ],
            vec!["info", p.to_str().unwrap()],
        ] {
            let (code, _stdout, stderr) = run(&args);
            assert_ne!(code, 0, "{name}: {args:?} succeeded");
            assert!(!stderr.contains("panicked"), "{name}: panic: {stderr}");
            let prefix = format!("error: {}:{line}: ", p.display());
            assert!(
                stderr.contains(&prefix),
                "{name}: expected '{prefix}' in: {stderr}"
            );
            assert!(
                stderr.contains(want),
                "{name}: expected '{want}' in: {stderr}"
            );
        }
    }
}

#[test]
fn missing_file_and_loop_on_quads() {
    let (code, _, err) = run(&[
        "tessellate",
        "/nonexistent/x.obj",
        "--depth",
        "1",
        "-o",
        "/tmp/x.obj",
    ]);
    assert_ne!(code, 0);
    assert!(err.starts_with("error: /nonexistent/x.obj: "), "{err}");
    // The I/O cause is printed once (not in the message and again as a `caused by:` line).
    assert_eq!(err.matches("(os error").count(), 1, "{err}");
    assert_eq!(err.matches("/nonexistent/x.obj").count(), 1, "{err}");
    let cube = fixtures().join("reference/shapes/catmark_cube.obj");
    let out = tmp("loopcube.obj");
    let (code, _, err) = run(&[
        "tessellate",
        cube.to_str().unwrap(),
        "--scheme",
        "loop",
        "--depth",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("Loop subdivision needs a triangle mesh"),
        "{err}"
    );
}

#[test]
fn tessellate_writes_limit_obj() {
    let cube = fixtures().join("reference/shapes/catmark_cube.obj");
    let out = tmp("cube2.obj");
    let (code, stdout, err) = run(&[
        "tessellate",
        cube.to_str().unwrap(),
        "--depth",
        "2",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("98 vertices, 96 faces"), "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 98);
    assert_eq!(text.lines().filter(|l| l.starts_with("vn ")).count(), 98);
    assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 96);
    // The written limit surface re-reads as a valid closed mesh.
    let m = subdiv_mesh::read_obj(&out).unwrap();
    assert_eq!(subdiv_mesh::MeshStats::of(&m).boundary_loops, 0);
}

/// UVs go through the uniform tessellation of both schemes: `vt` and `f v/vt/vn` corners, the
/// cage's seams kept (a corner of the cube's unwrap keeps its value at every depth).
#[test]
fn tessellate_writes_texture_coordinates() {
    for (cage, scheme, faces) in [("cube_uv", "catmull-clark", 96), ("tri_seam", "loop", 128)] {
        let input = fixtures().join(format!("meshes/fvar/{cage}.obj"));
        let out = tmp(&format!("{cage}.uv.obj"));
        let (code, _, err) = run(&[
            "tessellate",
            input.to_str().unwrap(),
            "--scheme",
            scheme,
            "--depth",
            "2",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let m = subdiv_mesh::read_obj(&out).unwrap();
        assert_eq!(m.num_faces(), faces);
        let fv = m.uv().expect("texture coordinates written");
        let text = std::fs::read_to_string(&out).unwrap();
        let corner = text.lines().find(|l| l.starts_with("f ")).unwrap();
        assert_eq!(
            corner.split(' ').nth(1).unwrap().split('/').count(),
            3,
            "{corner}"
        );
        // Every value stays inside the cage's UV range; the unwrap's corners are kept.
        assert!(
            fv.values
                .iter()
                .all(|t| t.x >= -0.1 && t.x <= 1.0 && t.y >= -0.1 && t.y <= 1.0)
        );
        if cage == "cube_uv" {
            assert!(fv.values.contains(&glam::Vec2::new(0.25, 0.0)));
        }
    }
}

#[test]
fn info_reports_topology() {
    let torus = fixtures().join("meshes/cc_3torus.obj");
    let (code, stdout, _) = run(&["info", torus.to_str().unwrap()]);
    assert_eq!(code, 0);
    for want in [
        "vertices: 19",
        "faces: 23",
        "genus: 3",
        "boundary loops: 0",
        "status: ok",
    ] {
        assert!(stdout.contains(want), "missing '{want}' in {stdout}");
    }
    // The teapot's spout and lid meet the body at single vertices: accepted as OpenSubdiv
    // takes it, with the non-manifold vertices named.
    let teapot = fixtures().join("meshes/tri_teapot.obj");
    let (code, stdout, err) = run(&["info", teapot.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}{err}");
    assert!(
        stdout.contains("non-manifold vertices: ") && stdout.contains("status: ok"),
        "{stdout}{err}"
    );
    let fin = fixtures().join("nonmanifold/fin3_quads.obj");
    let (code, stdout, err) = run(&["info", fin.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}{err}");
    for want in [
        "non-manifold edges: 1 (0-1: 3 faces)",
        "non-manifold vertices: 2 (0: 3 fans, 1: 3 fans)",
        "status: ok",
    ] {
        assert!(stdout.contains(want), "missing '{want}' in {stdout}");
    }
    let (code, stdout, _) = run(&["info", "--split-nonmanifold", teapot.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(
        stdout.contains("boundary loops: ") && stdout.contains("loop yes"),
        "{stdout}"
    );
}

#[test]
fn adaptive_and_doi_tessellation() {
    let pawn = fixtures().join("reference/shapes/catmark_pawn.obj");
    let out = tmp("pawn_adaptive.obj");
    let (code, stdout, err) = run(&[
        "tessellate",
        pawn.to_str().unwrap(),
        "--eye-relative",
        "0.3,0.4,2.5",
        "--max-depth",
        "3",
        "--stats",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("patches per depth: 0:"), "{stdout}");
    let tris: usize = stdout
        .lines()
        .find_map(|l| l.strip_prefix("triangles: "))
        .unwrap()
        .parse()
        .unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), tris);
    // The adaptive mesh is a valid, edge-manifold mesh (only the pawn's own boundary is open).
    let m = subdiv_mesh::read_obj(&out).unwrap();
    assert_eq!(subdiv_mesh::MeshStats::of(&m).boundary_loops, 1);
    // DoI-driven depths for Catmull-Clark: the dihedral DoI needs no camera.
    let (code, stdout, err) = run(&[
        "tessellate",
        pawn.to_str().unwrap(),
        "--doi",
        "dihedral",
        "--stats",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("adaptive/uniform"), "{stdout}");
    // Absurd depths are refused before allocating: beyond this machine's memory (with the size
    // asked for), else beyond the slates' point limit.
    let (code, _, err) = run(&[
        "tessellate",
        pawn.to_str().unwrap(),
        "--depth",
        "11",
        "-o",
        "/tmp/never.obj",
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("depth 11 on 588 faces asks for 2,466,250,752 quads")
            || (err.contains("would produce") && err.contains("limit points")),
        "{err}"
    );
    // Bad values are errors, not panics.
    for bad in [
        vec!["--pixel-error", "-1", "--eye-relative", "0,0,3"],
        vec!["--projected-size", "8,2", "--eye-relative", "0,0,3"],
        vec![],
    ] {
        let mut args = vec!["tessellate", pawn.to_str().unwrap(), "-o", "/tmp/never.obj"];
        args.extend(bad.iter().copied());
        let (code, _, err) = run(&args);
        assert_ne!(code, 0);
        assert!(err.starts_with("error"), "{err}");
        assert!(!err.contains("panicked"));
    }
}

/// Tag lines subdiv does not apply: a located warning on stderr (and a line in `info`), an
/// error with `--strict` for every command that reads a cage.
#[test]
fn ignored_tags_warn_and_strict_refuses() {
    let cage = tmp("ignored_tags.obj");
    std::fs::write(
        &cage,
        format!(
            "{QUAD_HEAD}f 1 2 3 4\nt bogustag 0/0/0\nt vertexedit 1/3/2 0 1 2 3 value set\n\
             t smoothtriangles 0/0/1 smooth\n"
        ),
    )
    .unwrap();
    let c = cage.to_str().unwrap();
    let (code, stdout, err) = run(&["info", c]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("ignored tags: 2 (line 6: t bogustag, line 7: t vertexedit)"),
        "{stdout}"
    );
    assert!(
        stdout.contains("triangles=smooth") && stdout.contains("status: ok"),
        "{stdout}"
    );
    assert!(
        err.contains(&format!(
            "warning: {c}:6: tag 't bogustag' ignored (unknown tag)"
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!("warning: {c}:7: tag 't vertexedit' ignored")),
        "{err}"
    );
    let (code, stdout, err) = run(&["info", "--strict", c]);
    assert_eq!(code, 1);
    assert!(stdout.contains("status: refused"), "{stdout}");
    assert!(
        err.contains(&format!(
            "error: {c}:6: 2 tag line(s) not applied (--strict)"
        )),
        "{err}"
    );

    let out = tmp("ignored_tags_out.obj");
    let o = out.to_str().unwrap();
    let (code, _, err) = run(&["tessellate", c, "--depth", "1", "-o", o]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains(&format!("warning: {c}:6:")), "{err}");
    let (code, _, err) = run(&["tessellate", "--strict", c, "--depth", "1", "-o", o]);
    assert_eq!(code, 1);
    assert!(
        err.contains("not applied (--strict)") && !err.contains("panicked"),
        "{err}"
    );
    // A cage without such tags is unaffected by --strict.
    let cube = fixtures().join("reference/shapes/catmark_cube.obj");
    let (code, _, err) = run(&["info", "--strict", cube.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning"), "{err}");
}

/// `-q` silences warnings (errors stay), `-v` adds the libraries' debug lines, and a piped run
/// carries no progress bar: stdout holds exactly the scripted lines and stderr nothing.
#[test]
fn quiet_verbose_and_no_progress_bar_when_piped() {
    let cage = tmp("quiet_tags.obj");
    std::fs::write(&cage, format!("{QUAD_HEAD}f 1 2 3 4\nt bogustag 0/0/0\n")).unwrap();
    let c = cage.to_str().unwrap();
    let out = tmp("quiet_out.obj");
    let o = out.to_str().unwrap();
    let (code, _, err) = run(&["tessellate", c, "--depth", "1", "-o", o]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning: "), "{err}");
    let (code, stdout, err) = run(&["-q", "tessellate", c, "--depth", "1", "-o", o]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "", "-q prints nothing on success");
    assert!(stdout.starts_with("tessellated "), "{stdout}");
    let (code, _, err) = run(&["tessellate", c, "-q", "--strict", "--depth", "1", "-o", o]);
    assert_eq!(code, 1);
    assert!(
        err.starts_with("error: ") && !err.contains("warning"),
        "{err}"
    );

    let (code, _, err) = run(&["tessellate", "-v", c, "--depth", "1", "-o", o]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains(&format!(
            "debug: subdiv::load: read {c}: 4 vertices, 1 faces"
        )),
        "{err}"
    );
    assert!(
        err.contains("debug: subdiv::scene: uniform CatmullClark depth 1"),
        "{err}"
    );
    assert!(err.contains("warning: "), "-v keeps warnings: {err}");
    let (code, _, err) = run(&["-q", "-v", "info", c]);
    assert_eq!(code, 2, "-q and -v conflict: {err}");

    // Work long enough for a bar on a terminal: piped, only the scripted lines.
    let cube = fixtures().join("reference/shapes/catmark_cube.obj");
    let cube = cube.to_str().unwrap();
    let (code, stdout, err) = run(&["tessellate", cube, "--depth", "6", "--stats", "-o", o]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "");
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 3, "{stdout}");
    assert!(lines[0].starts_with(&format!("tessellated {cube}: 24578 vertices, 24576 faces")));
    assert_eq!(lines[1], "patches per depth: 6:6");
    assert_eq!(lines[2], "triangles: 49152");
    let (code, stdout, err) = run(&["bench", "tessellate", cube, "--depth", "4", "--runs", "3"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "");
    assert_eq!(stdout.lines().count(), 2, "{stdout}");
    for text in [&stdout, &err] {
        assert!(!text.contains('\r') && !text.contains('\u{1b}'), "{text:?}");
    }
}

/// `bench tessellate` says what it timed: a frame (points, normals and indices) by default,
/// points and normals with `--points-only`; both tessellate the same points.
#[test]
fn bench_tessellate_says_what_it_timed() {
    let fields = |args: &[&str]| -> Vec<(String, String)> {
        let (code, stdout, err) = run(args);
        assert_eq!(code, 0, "{err}");
        let last = stdout.lines().last().unwrap_or_default().to_string();
        let first = stdout.lines().next().unwrap_or_default().to_string();
        assert!(last.starts_with("limit_points_per_s="), "{stdout}");
        format!("{first} {last}")
            .split_whitespace()
            .filter_map(|kv| kv.split_once('='))
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    };
    let get = |f: &[(String, String)], k: &str| -> Vec<String> {
        f.iter()
            .filter(|(n, _)| n == k)
            .map(|(_, v)| v.clone())
            .collect()
    };
    let cube = fixtures().join("reference/shapes/catmark_cube.obj");
    let tet = fixtures().join("reference/shapes/loop_icosahedron.obj");
    for (cage, scheme) in [(&cube, "catmull-clark"), (&tet, "loop")] {
        let c = cage.to_str().unwrap();
        let base = ["bench", "tessellate", c, "--scheme", scheme, "--depth", "3"];
        let frame = fields(&[&base[..], &["--runs", "2"]].concat());
        let points = fields(&[&base[..], &["--runs", "2", "--points-only"]].concat());
        assert_eq!(
            get(&frame, "timed"),
            ["points+normals+indices"; 2],
            "{frame:?}"
        );
        assert_eq!(get(&points, "timed"), ["points+normals"; 2], "{points:?}");
        assert_eq!(get(&frame, "limit_points"), get(&points, "limit_points"));
    }
}

/// `subdiv view --help` lists the viewer's keys and mouse.
#[test]
fn view_help_lists_the_keys() {
    let (code, stdout, err) = run(&["view", "--help"]);
    assert_eq!(code, 0, "{err}");
    for want in [
        "middle drag, shift + left drag pan",
        "Home, F",
        "--up",
        "--no-hud",
        "--pan",
    ] {
        assert!(stdout.contains(want), "no '{want}' in:\n{stdout}");
    }
}

/// A closed pipe on stdout (`subdiv info CAGE | head -0`) ends the command quietly with status 0,
/// not with a panic. The read end is closed before the command starts, so every write fails.
#[test]
fn closed_stdout_pipe_is_not_a_panic() {
    let cube = fixtures().join("reference/shapes/catmark_cube.obj");
    let cube = cube.to_str().unwrap();
    let out = tmp("closed_pipe.obj");
    let o = out.to_str().unwrap();
    for args in [
        vec!["info", cube],
        vec!["tessellate", cube, "--depth", "2", "--stats", "-o", o],
    ] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let done = common::subdiv()
            .args(&args)
            .stdout(writer)
            .output()
            .unwrap();
        let err = common::stderr(&done);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(done.status.code(), Some(0), "{args:?}: {err}");
    }
}
