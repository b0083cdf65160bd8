//! The adaptive paths of `subdiv render` and `subdiv bench framerate` end to end: images and
//! per-frame lines are written, bad flag values give `error:` and a non-zero exit, never a panic.
//!
//! Without a Vulkan driver the tests that render print a note and pass, unless
//! `SUBDIV_VK_REQUIRE_DRIVER=1` (set by `cargo xtask test`).

mod common;

use std::path::PathBuf;

use common::{assert_fails, root, run, run_ok, tmp};
use subdiv_vk::read_png;

fn pawn() -> PathBuf {
    root().join("fixtures/reference/shapes/catmark_pawn.obj")
}

#[test]
fn adaptive_render_writes_a_depth_coloured_image() {
    let out = tmp("pawn.png");
    let input = pawn();
    let Some(o) = run_ok(&[
        "render",
        input.to_str().unwrap(),
        "--up",
        "0,0,1",
        "--eye-relative",
        "1.5,-1.7,0.9",
        "--max-depth",
        "3",
        "--shading",
        "depth",
        "--wire-overlay",
        "--size",
        "160x160",
        "-o",
        out.to_str().unwrap(),
    ]) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("adaptive"), "{stdout}");
    let img = read_png(&out).unwrap();
    assert_eq!(img.dimensions(), (160, 160));
    // Depth colours are not grey: some pixel has unequal channels.
    assert!(
        img.pixels().any(|p| p.0[0] != p.0[1] || p.0[1] != p.0[2]),
        "no coloured pixel in a depth-shaded render"
    );
    // The culling camera from behind changes the depths, hence the image.
    let behind = tmp("pawn-behind.png");
    let Some(_) = run_ok(&[
        "render",
        input.to_str().unwrap(),
        "--up",
        "0,0,1",
        "--eye-relative",
        "1.5,-1.7,0.9",
        "--cull-camera-eye-relative",
        "-1.5,1.7,0.9",
        "--max-depth",
        "3",
        "--shading",
        "depth",
        "--size",
        "160x160",
        "-o",
        behind.to_str().unwrap(),
    ]) else {
        return;
    };
    assert!(read_png(&behind).unwrap() != img);
}

#[test]
fn bench_framerate_prints_one_line_per_frame() {
    let Some(o) = run_ok(&[
        "bench",
        "framerate",
        "--frames",
        "5",
        "--size",
        "96x64",
        "--max-depth",
        "2",
    ]) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = stdout.lines().filter(|l| l.starts_with("frame=")).collect();
    assert_eq!(lines.len(), 5, "{stdout}");
    for (i, l) in lines.iter().enumerate() {
        let f: Vec<&str> = l.split_whitespace().collect();
        assert_eq!(f[0], format!("frame={i}"), "{l}");
        let fps: f64 = f[1].strip_prefix("fps=").unwrap().parse().unwrap();
        assert!(fps.is_finite() && fps > 0.0, "{l}");
        let tris: u64 = f[2].strip_prefix("triangles=").unwrap().parse().unwrap();
        assert!(tris > 0, "{l}");
        let cap: u8 = f[3].strip_prefix("maxsd=").unwrap().parse().unwrap();
        assert!(cap <= 2, "{l}");
        // The helmets are all quads among quads: a patch at depth d is 4^d quads.
        let per = |k: usize, key: &str| -> Vec<u64> {
            f[k].strip_prefix(key)
                .unwrap()
                .split(',')
                .map(|x| x.parse().unwrap())
                .collect()
        };
        let (patches, quads) = (per(4, "patches="), per(5, "quads="));
        assert_eq!(patches.len(), quads.len(), "{l}");
        for (d, (p, q)) in patches.iter().zip(&quads).enumerate() {
            assert_eq!(p * 4u64.pow(d as u32), *q, "{l}");
        }
    }
}

/// The paper's parameters reach `bench framerate`: a finer projected-size band draws more of the
/// far helmets, the default band given explicitly draws what no flag draws, and bad values are
/// refused by name.
#[test]
fn bench_framerate_takes_the_paper_modes_parameters() {
    let triangles = |extra: &[&str]| -> u64 {
        let mut args = vec![
            "bench",
            "framerate",
            "--no-render",
            "--frames",
            "1",
            "--size",
            "320x240",
        ];
        args.extend(extra);
        let (code, stdout, err) = run(&args);
        assert_eq!(code, 0, "{err}");
        let tris = stdout
            .split_whitespace()
            .find_map(|w| w.strip_prefix("triangles="))
            .unwrap_or_else(|| panic!("no triangles= in {stdout}"));
        tris.parse().unwrap()
    };
    let default = triangles(&[]);
    let (lo, hi) = subdiv::depth::DEFAULT_PROJECTED_SIZE;
    let band = format!("{lo},{hi}");
    assert_eq!(triangles(&["--projected-size", &band]), default);
    let finer = triangles(&["--projected-size", "0.25,4"]);
    assert!(finer > default, "{finer} <= {default}");
    let coarser = triangles(&["--cone-aperture", "60", "--projected-size", "4,16"]);
    assert!(coarser < default, "{coarser} >= {default}");
    assert_fails(
        &["bench", "framerate", "--cone-aperture", "0"],
        "--cone-aperture",
    );
    assert_fails(
        &["bench", "framerate", "--classifier", "1.5"],
        "--classifier",
    );
    assert_fails(
        &["bench", "framerate", "--projected-size", "4,1"],
        "MIN <= MAX",
    );
    assert_fails(
        &["bench", "framerate", "--depth", "2", "--classifier", "0.2"],
        "--classifier",
    );
}

#[test]
fn bench_framerate_measures_image_error_every_kth_frame() {
    let run = |depth: &str| {
        let mut args = vec![
            "bench",
            "framerate",
            "--frames",
            "3",
            "--no-render",
            "--size",
            "96x64",
            "--error-size",
            "160x120",
            "--error-every",
            "2",
            "--max-depth",
            "2",
        ];
        if !depth.is_empty() {
            args.extend(["--depth", depth]);
        }
        let o = run_ok(&args)?;
        let stdout = String::from_utf8_lossy(&o.stdout).to_string();
        let lines: Vec<String> = stdout
            .lines()
            .filter(|l| l.starts_with("frame="))
            .map(str::to_string)
            .collect();
        assert_eq!(lines.len(), 3, "{stdout}");
        assert!(!lines[1].contains("silhouette_px_max="), "{stdout}");
        let value = |l: &str, key: &str| -> f32 {
            l.split_whitespace()
                .find_map(|kv| kv.strip_prefix(key))
                .unwrap_or_else(|| panic!("no {key} in {l}"))
                .parse()
                .unwrap()
        };
        for l in [&lines[0], &lines[2]] {
            let max = value(l, "silhouette_px_max=");
            assert!(max >= value(l, "silhouette_px_p99=") && max >= 0.0, "{l}");
        }
        Some([
            value(&lines[0], "shading_deg_p99="),
            value(&lines[2], "shading_deg_p99="),
        ])
    };
    let (Some(coarse), Some(fine)) = (run("0"), run("2")) else {
        return;
    };
    // Against the depth-3 reference, the cage's (depth 0) normals are far off, depth 2's close.
    for k in 0..2 {
        assert!(
            coarse[k] > 2.0 * fine[k] && fine[k] > 0.0,
            "shading p99 {coarse:?} {fine:?}"
        );
    }
}

#[test]
fn bad_adaptive_flag_values_fail_cleanly() {
    let input = pawn();
    let input = input.to_str().unwrap();
    let out = tmp("never.png");
    let out = out.to_str().unwrap();
    assert_fails(
        &[
            "render",
            input,
            "--eye-relative",
            "1,1,1",
            "--pixel-error=-1",
            "-o",
            out,
        ],
        "--pixel-error",
    );
    assert_fails(
        &[
            "render",
            input,
            "--eye-relative",
            "1,1,1",
            "--projected-size",
            "8,2",
            "-o",
            out,
        ],
        "MIN <= MAX",
    );
    assert_fails(
        &[
            "render",
            input,
            "--eye-relative",
            "1,1,1",
            "--max-depth",
            "99",
            "-o",
            out,
        ],
        "max-depth",
    );
    assert_fails(
        &[
            "render",
            input,
            "--eye-relative",
            "1,1,1",
            "--cull-camera-eye-relative",
            "1,2",
            "-o",
            out,
        ],
        "X,Y,Z",
    );
    assert_fails(
        &[
            "render",
            input,
            "--depth",
            "2",
            "--cull-camera-eye-relative",
            "1,2,3",
            "-o",
            out,
        ],
        "cull-camera",
    );
    assert_fails(&["bench", "framerate", "--frames", "many"], "--frames");
    assert_fails(&["bench", "framerate", "--scene", "teapot"], "teapot");
    assert_fails(&["bench", "framerate", "--size", "0x10"], "size");
    assert_fails(
        &["bench", "framerate", "--error-every", "0"],
        "--error-every",
    );
    assert_fails(
        &["bench", "framerate", "--target-fps=-3", "--frames", "1"],
        "frame rates must be positive",
    );
}

/// An adaptive flag means the same in `tessellate`, `render` and `view`: without
/// `--depth` it asks for the adaptive tessellation (with the default camera when no camera flag
/// is given); next to `--depth` it is refused — never silently ignored; with Loop on a triangle
/// cage it applies as with Catmull-Clark.
#[test]
fn adaptive_flags_mean_the_same_in_every_command() {
    let input = root().join("fixtures/scenes/box_8_sharp_edges.obj");
    let input = input.to_str().unwrap();
    let png = tmp("flags.png");
    let png = png.to_str().unwrap();
    let obj = tmp("flags.obj");
    let obj = obj.to_str().unwrap();
    // No camera flag: the default camera, adaptive.
    if let Some(o) = run_ok(&["render", input, "--pixel-error", "1", "-o", png]) {
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(out.contains("adaptive, max depth 5"), "{out}");
    }
    let (code, out, err) = run(&[
        "tessellate",
        input,
        "--pixel-error",
        "1",
        "--stats",
        "-o",
        obj,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("triangles"), "{out}");
    // Next to --depth: refused, naming the flags.
    for cmd in ["render", "tessellate", "view"] {
        let out_file = if cmd == "tessellate" { obj } else { png };
        let mut args = vec![
            cmd,
            input,
            "--depth",
            "2",
            "--pixel-error",
            "1",
            "--cull-back",
        ];
        if cmd == "view" {
            args.extend(["--screenshot-after", "1"]);
        }
        args.extend(["-o", out_file]);
        let (code, _, err) = run(&args);
        assert_eq!(code, 1, "{cmd}: {err}");
        assert!(
            err.contains("--pixel-error, --cull-back choose adaptive depths"),
            "{cmd}: {err}"
        );
    }
    // Loop: every adaptive mode (camera, curvature flags, pixel error, culling, a DoI) on a
    // triangle cage; the quad cage is refused as Loop refuses it, naming the face.
    let ico = root().join("fixtures/reference/shapes/loop_icosahedron.obj");
    let ico = ico.to_str().unwrap();
    let modes: [&[&str]; 5] = [
        &["--eye-relative", "0.3,0.2,2.5"],
        &["--cone-aperture", "5", "--projected-size", "1,4"],
        &["--pixel-error", "0.5", "--cull-back"],
        &[
            "--pixel-error",
            "1",
            "--shading-error",
            "5",
            "--max-depth",
            "4",
        ],
        &["--doi", "view-angle"],
    ];
    for mode in modes {
        let mut args = vec!["tessellate", ico, "--scheme", "loop", "--stats", "-o", obj];
        args.extend_from_slice(mode);
        let (code, out, err) = run(&args);
        assert_eq!(code, 0, "{mode:?}: {err}");
        assert!(out.contains("(adaptive, max depth"), "{mode:?}: {out}");
        assert!(out.contains("patches per depth: "), "{mode:?}: {out}");
    }
    if let Some(o) = run_ok(&[
        "render",
        ico,
        "--scheme",
        "loop",
        "--pixel-error",
        "1",
        "-o",
        png,
    ]) {
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(out.contains("adaptive, max depth 5"), "{out}");
    }
    let (code, _, err) = run(&[
        "tessellate",
        input,
        "--scheme",
        "loop",
        "--pixel-error",
        "1",
        "-o",
        obj,
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("face 0 has 4 vertices; Loop subdivision needs a triangle"),
        "{err}"
    );
    let (code, _, err) = run(&[
        "tessellate",
        ico,
        "--scheme",
        "loop",
        "--simple-fans",
        "-o",
        obj,
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("--simple-fans chooses between the Catmull-Clark fan forms"),
        "{err}"
    );
}

/// `key=value` of a line, parsed.
fn field<T: std::str::FromStr>(line: &str, key: &str) -> T
where
    T::Err: std::fmt::Debug,
{
    line.split_whitespace()
        .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
        .unwrap_or_else(|| panic!("no {key}= in {line}"))
        .parse()
        .unwrap()
}

#[test]
fn bench_framerate_runs_any_cage_under_either_control() {
    // Three pawns, no rendering: every frame has its measured and predicted time and the
    // update's parts, which add up to at most the update; the summary line closes the run.
    let input = pawn();
    for control in ["budget", "paper"] {
        let (code, stdout, stderr) = run(&[
            "bench",
            "framerate",
            input.to_str().unwrap(),
            "--instances",
            "3",
            "--no-render",
            "--frames",
            "12",
            "--size",
            "160x120",
            "--max-depth",
            "3",
            "--target-fps",
            "400",
            "--switch-fps",
            "800",
            "--control",
            control,
        ]);
        assert_eq!(code, 0, "{stderr}");
        let head = stdout.lines().next().unwrap();
        assert!(head.contains("faces=1764"), "3 x 588 faces: {head}");
        assert!(head.contains(&format!("{control} control")), "{head}");
        let frames: Vec<&str> = stdout.lines().filter(|l| l.starts_with("frame=")).collect();
        assert_eq!(frames.len(), 12, "{stdout}");
        for l in &frames[1..] {
            let (ms, predicted): (f64, f64) = (field(l, "ms"), field(l, "predicted_ms"));
            assert!(ms > 0.0 && predicted > 0.0, "{l}");
            let parts: f64 = ["depths_ms", "tessellate_ms", "fans_ms", "upload_prep_ms"]
                .iter()
                .map(|k| field::<f64>(l, k))
                .sum();
            assert!(parts <= field::<f64>(l, "update_ms") + 0.01, "{l}");
        }
        let summary = stdout.lines().last().unwrap();
        assert!(summary.starts_with("summary frames=12"), "{summary}");
        assert_eq!(field::<usize>(summary, "switch_frame"), 6, "{summary}");
    }
}

#[test]
fn bench_framerate_calibrates_before_the_run() {
    let Some(o) = run_ok(&[
        "bench",
        "framerate",
        "--scene",
        "helmet40",
        "--instances",
        "2",
        "--calibrate",
        "--frames",
        "2",
        "--size",
        "96x64",
        "--max-depth",
        "2",
    ]) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&o.stdout);
    let cal = stdout
        .lines()
        .find(|l| l.starts_with("calibrate "))
        .unwrap_or_else(|| panic!("no calibrate line: {stdout}"));
    assert_eq!(field::<usize>(cal, "frames"), 30, "{cal}");
    let share: f64 = field(cal, "ceiling_within10");
    assert!((0.0..=1.0).contains(&share), "{cal}");
    assert!(
        (share * 30.0 - (share * 30.0).round()).abs() < 0.02,
        "a share of 30 frames: {cal}"
    );
    assert!(field::<f64>(cal, "median_fps") > 0.0, "{cal}");
    assert!(stdout.contains("faces=116"), "two helmets: {stdout}");
    // Contradictory flags are refused.
    assert_fails(
        &[
            "bench",
            "framerate",
            "--calibrate",
            "--no-render",
            "--frames",
            "1",
        ],
        "--calibrate",
    );
    assert_fails(
        &["bench", "framerate", "--instances", "0", "--frames", "1"],
        "--instances",
    );
}
