//! `subdiv evaluate`: the output line format, points from a file and at random, and bad lines
//! named by their line.

mod common;

use common::{assert_clean_failure, run, subdiv, tmp};

fn shape(name: &str) -> String {
    subdiv_test_support::shape(name).display().to_string()
}

/// `x,y,z` as three numbers.
fn vec3(s: &str) -> [f64; 3] {
    let v: Vec<f64> = s.split(',').map(|x| x.parse().unwrap()).collect();
    [v[0], v[1], v[2]]
}

/// The `key=value` fields of a line, in order.
fn fields(line: &str) -> Vec<(&str, &str)> {
    line.split(' ')
        .map(|f| f.split_once('=').unwrap())
        .collect()
}

#[test]
fn points_from_a_file_in_the_issue_format() {
    let points = tmp("cube_points.txt");
    std::fs::write(
        &points,
        "# face u v\n0 0.5 0.5\n\n3 0 1\n5 0.25 0.75 # a comment\n",
    )
    .unwrap();
    let cube = shape("catmark_cube.obj");
    let (code, out, err) = run(&["evaluate", &cube, "--uv", points.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    let keys: Vec<&str> = fields(lines[0]).iter().map(|f| f.0).collect();
    assert_eq!(keys, ["face", "u", "v", "p", "du", "dv"]);
    assert!(
        lines[0].starts_with("face=0 u=0.5 v=0.5 p="),
        "{}",
        lines[0]
    );
    assert!(lines[1].starts_with("face=3 u=0 v=1 p="), "{}", lines[1]);
    // The cube's limit is symmetric: the centre of a face lies on an axis of the cube.
    let p = vec3(fields(lines[0])[3].1);
    assert!(
        (p[0].abs() < 1e-12 || p[1].abs() < 1e-12 || p[2].abs() < 1e-12),
        "{p:?}"
    );
    // --second adds the second derivatives; -o writes the same lines to a file.
    let out2 = tmp("cube_eval.txt");
    let (code, summary, err) = run(&[
        "evaluate",
        &cube,
        "--uv",
        points.to_str().unwrap(),
        "--second",
        "-o",
        out2.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(summary.starts_with("evaluated 3 points of"), "{summary}");
    let text = std::fs::read_to_string(&out2).unwrap();
    let first = text.lines().next().unwrap();
    let keys: Vec<&str> = fields(first).iter().map(|f| f.0).collect();
    assert_eq!(
        keys,
        ["face", "u", "v", "p", "du", "dv", "duu", "duv", "dvv"]
    );
    assert!(first.starts_with(lines[0]), "{first}\n{}", lines[0]);
}

#[test]
fn random_points_are_reproducible_and_in_the_domain() {
    let pawn = shape("catmark_pawn.obj");
    let a = run(&["evaluate", &pawn, "--uv", "random:50:7"]);
    let b = run(&["evaluate", &pawn, "--uv", "random:50:7"]);
    let c = run(&["evaluate", &pawn, "--uv", "random:50:8"]);
    assert_eq!(a.0, 0, "{}", a.2);
    assert_eq!(a.1, b.1);
    assert_ne!(a.1, c.1);
    assert_eq!(a.1.lines().count(), 50);
    // Loop triangles: barycentric (u, v).
    let ico = shape("loop_icosahedron.obj");
    let (code, out, err) = run(&["evaluate", &ico, "--scheme", "loop", "--uv", "random:40"]);
    assert_eq!(code, 0, "{err}");
    for line in out.lines() {
        let f = fields(line);
        let (u, v): (f64, f64) = (f[1].1.parse().unwrap(), f[2].1.parse().unwrap());
        assert!(u >= 0.0 && v >= 0.0 && u + v <= 1.0, "{line}");
    }
}

#[test]
fn a_bad_line_is_an_error_naming_it() {
    let cube = shape("catmark_cube.obj");
    let cases = [
        (
            "0 0.5 0.5\n1 0.5\n",
            ":2: expected 'FACE U V', found '1 0.5'",
        ),
        ("0 0.5 0.5\n\nx 0 0\n", ":3: FACE must be a face index"),
        ("0 0.5 zero\n", ":1: V must be a number, found 'zero'"),
        (
            "0 0.5 0.5\n6 0 0\n",
            ":2: face 6 does not exist (the cage has 6 faces)",
        ),
        (
            "2 1.5 0\n",
            ":1: (u, v) = (1.5, 0) is outside face 2's domain, the unit square",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let points = tmp(&format!("bad_points_{i}.txt"));
        std::fs::write(&points, text).unwrap();
        let o = subdiv()
            .args(["evaluate", &cube, "--uv", points.to_str().unwrap()])
            .output()
            .unwrap();
        assert_clean_failure(&o, want);
        assert!(common::stderr(&o).contains(points.to_str().unwrap()));
    }
    let o = subdiv()
        .args(["evaluate", &cube, "--uv", "random:x"])
        .output()
        .unwrap();
    assert_clean_failure(&o, "N must be a count");
}

/// `tessellate --dicing-rate` writes each vertex's (face, u, v) to PLY (`face u v`) and glTF
/// (`_FACE`, `_PATCH_UV`), and evaluating that point gives the vertex.
#[test]
fn dicing_writes_each_vertex_parameter_point() {
    let pawn = shape("catmark_pawn.obj");
    let ply = tmp("pawn_diced.ply");
    let (code, out, err) = run(&[
        "tessellate",
        &pawn,
        "--dicing-rate",
        "24",
        "--stats",
        "-o",
        ply.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("edge rates: min="), "{out}");
    let bytes = std::fs::read(&ply).unwrap();
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let head = String::from_utf8_lossy(&bytes[..end]);
    assert!(
        head.contains("property uint face\nproperty float u\nproperty float v\n"),
        "{head}"
    );
    let n: usize = head
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .unwrap()
        .parse()
        .unwrap();
    // 6 floats, then face, u, v: 36 bytes a vertex.
    let vertex = |i: usize| {
        let b = &bytes[end + i * 36..end + (i + 1) * 36];
        let f = |k: usize| f32::from_le_bytes(b[4 * k..4 * k + 4].try_into().unwrap());
        let face = u32::from_le_bytes(b[24..28].try_into().unwrap());
        ([f(0), f(1), f(2)], face, f(7), f(8))
    };
    let points = tmp("pawn_diced_points.txt");
    let picks: Vec<usize> = (0..n).step_by(n / 40 + 1).collect();
    let text: String = picks
        .iter()
        .map(|&i| {
            let (_, face, u, v) = vertex(i);
            format!("{face} {u} {v}\n")
        })
        .collect();
    std::fs::write(&points, text).unwrap();
    let (code, out, err) = run(&["evaluate", &pawn, "--uv", points.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    for (line, &i) in out.lines().zip(&picks) {
        let p = vec3(fields(line)[3].1);
        let (q, ..) = vertex(i);
        let d = (0..3)
            .map(|k| (p[k] - f64::from(q[k])).abs())
            .fold(0.0, f64::max);
        assert!(d < 1e-4, "vertex {i}: {line} vs {q:?}");
    }
    let glb = tmp("pawn_diced.glb");
    let (code, _, err) = run(&[
        "tessellate",
        &pawn,
        "--dicing-rate",
        "24",
        "-o",
        glb.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = String::from_utf8_lossy(&std::fs::read(&glb).unwrap()).to_string();
    assert!(
        text.contains("\"_FACE\"") && text.contains("\"_PATCH_UV\""),
        "no _FACE / _PATCH_UV in the glTF JSON"
    );
}

/// Under the bilinear scheme the surface is the cage itself (a cube, turned by 45 degrees
/// about z), and the second derivatives along u and v vanish.
#[test]
fn bilinear_points_lie_on_the_cage() {
    let cube = shape("catmark_cube.obj");
    let args = [
        "evaluate",
        &cube,
        "--scheme",
        "bilinear",
        "--uv",
        "random:20:3",
        "--second",
    ];
    let (code, out, err) = run(&args);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().count(), 20);
    for line in out.lines() {
        let f = fields(line);
        let get = |k: &str| vec3(f.iter().find(|x| x.0 == k).unwrap().1);
        // On the top or bottom (z = ±1) or on a side (|x| + |y| = 1.414214).
        let p = get("p");
        let side = (p[0].abs() + p[1].abs() - std::f64::consts::SQRT_2).abs() < 1e-5;
        assert!(side || (p[2].abs() - 1.0).abs() < 1e-6, "{line}");
        assert_eq!((get("duu"), get("dvv")), ([0.0; 3], [0.0; 3]), "{line}");
    }
}
