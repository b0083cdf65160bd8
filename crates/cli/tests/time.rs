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
