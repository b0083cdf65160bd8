//! `--time T` through the `subdiv` binary: an animated stage read at a time code tessellates
//! exactly as the static cage Pixar's USD reads at that time (`fixtures/usd/make_animated.py`),
//! `subdiv info` prints the stage's time range, and a time is refused where it cannot apply.

mod common;

use common::{assert_fails, run, tmp};
use subdiv_test_support::fixtures;

fn usd(name: &str) -> String {
    fixtures().join("usd").join(name).display().to_string()
}

/// `subdiv tessellate INPUT FLAGS -o NAME`: the bytes written.
fn tessellate(input: &str, flags: &[&str], name: &str) -> Vec<u8> {
    let out = tmp(name);
    let mut args = vec!["tessellate", input];
    args.extend_from_slice(flags);
    args.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let (code, _, err) = run(&args);
    assert_eq!(code, 0, "{args:?}: {err}");
    std::fs::read(&out).unwrap()
}

#[test]
fn a_stage_at_a_time_tessellates_as_the_static_cage_at_that_time() {
    let uniform = ["--depth", "2"];
    let adaptive = ["--eye-relative", "1.5,-1.7,0.9", "--up", "0,0,1"];
    for (stage, t, truth) in [
        ("pawn_bend.usdc", "13", "pawn_bend_t13.obj"),
        ("pawn_bend.usdc", "30", "pawn_bend_t30.obj"),
        ("xform_anim.usda", "18.5", "xform_anim_t18_5.obj"),
    ] {
        for (kind, flags) in [("uniform", &uniform[..]), ("adaptive", &adaptive[..])] {
            let mut at = vec!["--time", t];
            at.extend_from_slice(flags);
            let a = tessellate(&usd(stage), &at, &format!("{stage}-{t}-{kind}.ply"));
            let b = tessellate(&usd(truth), flags, &format!("{truth}-{kind}.ply"));
            assert!(a == b, "{stage} at {t} ({kind}) differs from {truth}");
        }
    }
    // The frames differ: the pawn moves.
    let a = tessellate(
        &usd("pawn_bend.usdc"),
        &["--time", "1", "--depth", "1"],
        "p1.ply",
    );
    let b = tessellate(
        &usd("pawn_bend.usdc"),
        &["--time", "13", "--depth", "1"],
        "p13.ply",
    );
    assert!(a != b);
}

#[test]
fn info_prints_the_time_range_and_what_is_time_sampled() {
    let (code, out, err) = run(&["info", &usd("pawn_bend.usdc"), "--time", "13"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("time range: start=1 end=48 time_codes_per_second=24 (authored)\n"),
        "{out}"
    );
    assert!(
        out.contains("time-sampled: /World/Pawn.points (48 samples)\n"),
        "{out}"
    );
    assert!(out.contains("time: 13\n"), "{out}");
    let (code, out, _) = run(&["info", &usd("scene.usda")]);
    assert_eq!(code, 0);
    assert!(
        out.contains("time range: none (nothing is time-sampled)\n"),
        "{out}"
    );
}

#[test]
fn a_time_is_refused_for_obj_input_and_when_not_a_number() {
    let obj = usd("pawn_bend_t1.obj");
    let o = tmp("never.obj");
    let o = o.to_str().unwrap();
    assert_fails(
        &["tessellate", &obj, "--time", "3", "--depth", "1", "-o", o],
        "a time (3) can only be chosen in a USD file",
    );
    assert_fails(&["info", &obj, "--time", "3"], "--time is for USD input");
    assert_fails(
        &[
            "tessellate",
            &usd("pawn_bend.usdc"),
            "--time",
            "NaN",
            "--depth",
            "1",
            "-o",
            o,
        ],
        "time NaN is not a finite time code",
    );
}

/// `bench animate`: one line a frame at the stage's time codes (played again from the start
/// past its end), the index buffer kept on every frame of the uniform tessellation (points
/// through the stencil table), and the summary line; a cage without animation is swayed.
#[test]
fn bench_animate_prints_a_line_a_frame_and_the_summary() {
    let (code, out, err) = run(&[
        "bench",
        "animate",
        &usd("pawn_bend.usdc"),
        "--depth",
        "1",
        "--frames",
        "50",
        "--threads",
        "1",
    ]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 52, "{out}");
    assert!(
        lines[0].contains("depth=1 threads=1 frames=50 source=stage"),
        "{out}"
    );
    // The frames come from the limit stencil table.
    assert!(lines[0].ends_with(" path=stencils"), "{out}");
    let counts = |l: &str| l.split_once(" points=").unwrap().1.to_string();
    for (i, l) in lines[1..51].iter().enumerate() {
        let t = 1 + i % 48;
        let want = format!("frame={i} time={t} update_ms=");
        assert!(l.starts_with(&want), "{l}");
        // 588 quads at depth 1: 2352 quads in every frame, and the faces stay.
        assert!(l.ends_with(" faces=2352 topology_written=0"), "{l}");
        assert_eq!(counts(l), counts(lines[1]));
    }
    let last = lines[51];
    assert!(last.starts_with("frames=50 update_ms_median="), "{last}");
    assert!(last.contains(" points_per_s="), "{last}");

    let (code, out, err) = run(&[
        "bench",
        "animate",
        &usd("pawn_bend_t1.obj"),
        "--frames",
        "2",
        "--eye-relative",
        "1.5,-1.7,0.9",
        "--up",
        "0,0,1",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.lines().next().unwrap().contains("adaptive max_depth=5"),
        "{out}"
    );
    assert!(out.contains("source=sway"), "{out}");
    assert!(out.contains("\nframe=1 time=1 "), "{out}");
    assert!(out.contains("\nframes=2 update_ms_median="), "{out}");
}
