//! Resource limits end to end: a request beyond this machine's memory is refused before
//! anything is tessellated (exit code 1, the size asked for in the message), and
//! `--max-triangles N` refuses one triangle above the exact count and accepts it at the count,
//! on every command that tessellates or refines. None of these runs allocates the refused
//! output: each fails at once.

mod common;

use common::{assert_clean_failure, run, subdiv, tmp};

fn fixture(rel: &str) -> String {
    subdiv_test_support::fixture(rel)
        .to_str()
        .unwrap()
        .to_string()
}

fn pawn() -> String {
    fixture("reference/shapes/catmark_pawn.obj")
}

fn cube() -> String {
    fixture("reference/shapes/catmark_cube.obj")
}

fn teapot() -> String {
    fixture("meshes/tri_teapot.obj")
}

/// Runs `subdiv ARGS` expecting exit code 1 with `want` in the error line.
fn refused(args: &[&str], want: &str) {
    // `-q`: the error line alone (the teapot's non-manifold warning left out).
    let o = subdiv().arg("-q").args(args).output().unwrap();
    assert_clean_failure(&o, want);
}

/// The pawn (588 faces, 2,352 corners) at depth 12: 2,352 * 4^11 quads.
const PAWN_DEPTH_12: &str =
    "depth 12 on 588 faces asks for 9,865,003,008 quads (19,730,006,016 triangles, ";

/// Depth 12 on the pawn is beyond any machine's memory: `tessellate`, `render`, `view` and
/// `bench tessellate` refuse it with the size and the memory.
#[test]
fn deep_uniform_requests_are_refused_by_memory() {
    if !cfg!(target_os = "linux") {
        return;
    }
    let out = tmp("deep.obj");
    let png = tmp("deep.png");
    let (pawn, out, png) = (pawn(), out.to_str().unwrap(), png.to_str().unwrap());
    for args in [
        vec!["tessellate", &pawn, "--depth", "12", "-o", out],
        vec!["render", &pawn, "--depth", "12", "-o", png],
        vec!["view", &pawn, "--depth", "12"],
        vec!["bench", "tessellate", &pawn, "--depth", "12"],
    ] {
        let o = subdiv().args(&args).output().unwrap();
        assert_clean_failure(&o, PAWN_DEPTH_12);
        let err = common::stderr(&o);
        assert!(err.contains("of memory available"), "{args:?}: {err}");
        assert!(err.contains("catmark_pawn.obj: depth 12"), "{err}");
    }
    assert!(!std::path::Path::new(out).exists(), "nothing was written");
}

/// The adaptive path at the deepest `--max-depth` and a DoI refinement by 12 steps are refused
/// by their bounds.
#[test]
fn deep_adaptive_and_refine_requests_are_refused_by_memory() {
    if !cfg!(target_os = "linux") {
        return;
    }
    let out = tmp("deep_adaptive.obj");
    let png = tmp("deep_adaptive.png");
    let (pawn, teapot) = (pawn(), teapot());
    let (out, png) = (out.to_str().unwrap(), png.to_str().unwrap());
    let eye = ["--eye-relative", "0,0.3,2.5"];
    refused(
        &[
            &["tessellate", &pawn, "--max-depth", "11", "-o", out][..],
            &eye,
        ]
        .concat(),
        "max depth 11 on 588 faces asks for at most ",
    );
    refused(
        &[&["render", &pawn, "--max-depth", "11", "-o", png][..], &eye].concat(),
        "of memory available",
    );
    refused(
        &[
            "refine", &teapot, "--doi", "dihedral", "--steps", "12", "-o", out,
        ],
        "12 refinement steps on 992 triangles asks for at most 16,642,998,272 triangles",
    );
    refused(
        &[
            "render", &teapot, "--doi", "dihedral", "--steps", "12", "-o", png,
        ],
        "of memory available",
    );
}

/// `--max-triangles` on the uniform tessellation: the cube at depth 3 is 768 triangles, the
/// teapot under Loop at depth 2 15,872; one fewer is refused naming the limit, the count itself
/// is accepted (and is the count written).
#[test]
fn max_triangles_is_exact_for_uniform_depth() {
    let out = tmp("limit.obj");
    let (cube, teapot, out) = (cube(), teapot(), out.to_str().unwrap());
    refused(
        &[
            "tessellate",
            &cube,
            "--depth",
            "3",
            "--max-triangles",
            "767",
            "-o",
            out,
        ],
        "depth 3 on 6 faces asks for 384 quads (768 triangles, 386 vertices, about 16.6 KiB of \
         output); the limit is 767 triangles (--max-triangles)",
    );
    let args = [
        "tessellate",
        &cube,
        "--depth",
        "3",
        "--max-triangles",
        "768",
        "--stats",
        "-o",
        out,
    ];
    let (code, stdout, err) = run(&args);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("386 vertices, 384 faces"), "{stdout}");
    assert!(stdout.contains("triangles: 768\n"), "{stdout}");
    let lp = [
        "tessellate",
        &teapot,
        "--scheme",
        "loop",
        "--depth",
        "2",
        "-o",
        out,
    ];
    refused(
        &[&lp[..], &["--max-triangles", "15871"]].concat(),
        "depth 2 on 992 faces asks for 15,872 triangles (",
    );
    let (code, stdout, err) = run(&[&lp[..], &["--max-triangles", "15872"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains(", 15872 faces (loop, depth 2)"), "{stdout}");
    let bench = ["bench", "tessellate", &cube, "--depth", "3", "--runs", "1"];
    refused(
        &[&bench[..], &["--max-triangles", "767"]].concat(),
        "the limit is 767",
    );
    let (code, stdout, err) = run(&[&bench[..], &["--max-triangles", "768"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains(" quads=384 "), "{stdout}");
}

/// `--max-triangles` on the adaptive path and on refinement refuses by the bound: the pawn at
/// max depth 5 is at most 2,352 patches of `2·4^4 + 8·2^4 + 16` triangles; two DoI steps on the
/// teapot at most `992·4^2` triangles (what refining every face gives).
#[test]
fn max_triangles_bounds_adaptive_and_refine() {
    let out = tmp("limit_adaptive.obj");
    let (pawn, teapot, out) = (pawn(), teapot(), out.to_str().unwrap());
    let adaptive = [
        "tessellate",
        &pawn,
        "--eye-relative",
        "0,0.3,2.5",
        "-o",
        out,
    ];
    refused(
        &[&adaptive[..], &["--max-triangles", "1542911"]].concat(),
        "max depth 5 on 588 faces asks for at most 1,542,912 triangles (",
    );
    let (code, stdout, err) = run(&[&adaptive[..], &["--max-triangles", "1542912"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("triangles (adaptive, max depth 5)"),
        "{stdout}"
    );
    let refine = [
        "refine", &teapot, "--doi", "dihedral", "--steps", "2", "-o", out,
    ];
    refused(
        &[&refine[..], &["--max-triangles", "15871"]].concat(),
        "2 refinement steps on 992 triangles asks for at most 15,872 triangles (",
    );
    let (code, stdout, err) = run(&[&refine[..], &["--max-triangles", "15872"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("refined "), "{stdout}");
}

/// The commands that draw or benchmark refuse before starting the renderer, so these need no
/// Vulkan driver.
#[test]
fn max_triangles_on_render_view_and_benchmarks() {
    let png = tmp("limit.png");
    let (cube, png) = (cube(), png.to_str().unwrap());
    let want = "depth 3 on 6 faces asks for 384 quads (768 triangles";
    refused(
        &["render", &cube, "--max-triangles", "767", "-o", png],
        want,
    );
    refused(&["view", &cube, "--max-triangles", "767"], want);
    refused(
        &[
            "view",
            &cube,
            "--doi",
            "dihedral",
            "--triangulate",
            "--max-triangles",
            "10",
        ],
        "3 refinement steps on 12 triangles asks for at most 768 triangles",
    );
    refused(
        &[
            "bench",
            "quality",
            &cube,
            "--max-depth",
            "2",
            "--max-triangles",
            "767",
        ],
        "depth 3 on 6 faces asks for 384 quads (768 triangles",
    );
    refused(
        &["bench", "framerate", "--no-render", "--max-triangles", "10"],
        "max depth 4 on ",
    );
}

/// Every command that tessellates or refines documents `--max-triangles`.
#[test]
fn max_triangles_is_in_every_help() {
    for cmd in [
        &["tessellate"][..],
        &["render"],
        &["view"],
        &["refine"],
        &["bench", "tessellate"],
        &["bench", "quality"],
        &["bench", "framerate"],
    ] {
        let (code, stdout, err) = run(&[cmd, &["--help"]].concat());
        assert_eq!(code, 0, "{err}");
        assert!(stdout.contains("--max-triangles <N>"), "{cmd:?}: {stdout}");
        assert!(
            stdout.contains("this machine's memory"),
            "{cmd:?}: {stdout}"
        );
    }
}
