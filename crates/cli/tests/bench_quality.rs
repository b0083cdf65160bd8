//! `subdiv bench quality` end to end: the line format of a tiny run, and the refusal of a
//! reference that is not deeper than the configurations. Without a Vulkan driver the run test
//! prints a note and passes, unless `SUBDIV_VK_REQUIRE_DRIVER=1`.

mod common;

use common::{assert_clean_failure, run_ok, subdiv};
use subdiv_test_support::shape;

const KEYS: [&str; 8] = [
    "config",
    "triangles",
    "silhouette_px_max",
    "silhouette_px_p99",
    "shading_deg_p99",
    "update_ms",
    "render_ms",
    "shading_deg_p99_off_lines",
];

fn cube() -> String {
    shape("catmark_cube.obj").to_string_lossy().into_owned()
}

/// The fields of a result line, checked against [`KEYS`] in order; numbers parse and are finite.
fn fields(line: &str) -> Vec<(String, f64)> {
    let tokens: Vec<&str> = line.split(' ').collect();
    assert_eq!(tokens.len(), KEYS.len(), "{line}");
    let mut out = Vec::new();
    for (t, key) in tokens.iter().zip(KEYS) {
        let (k, v) = t.split_once('=').unwrap_or_else(|| panic!("{t} in {line}"));
        assert_eq!(k, key, "{line}");
        if key == "config" {
            out.push((v.to_string(), 0.0));
        } else if key == "triangles" {
            out.push((key.to_string(), v.parse::<u64>().expect(line) as f64));
        } else {
            let x: f64 = v.parse().expect(line);
            assert!(x.is_finite() && x >= 0.0, "{line}");
            out.push((key.to_string(), x));
        }
    }
    out
}

/// The output of `bench quality ARGS` at maximum depth 4 against uniform depth 5, one timing
/// run (`None`: no Vulkan driver, and none required).
fn depth4_run(args: &[&str]) -> Option<String> {
    let mut all = vec!["bench", "quality"];
    all.extend(args);
    all.extend(["--max-depth", "4", "--reference-depth", "5", "--runs", "1"]);
    run_ok(&all).map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
}

/// The fields of the last `config=NAME` line of a run's output.
fn config_fields(stdout: &str, name: &str) -> Vec<(String, f64)> {
    let line = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with(&format!("config={name} ")))
        .unwrap_or_else(|| panic!("no {name} in {stdout}"));
    fields(line)
}

#[test]
fn tiny_run_prints_one_line_per_configuration_last() {
    let input = cube();
    let Some(o) = run_ok(&[
        "bench",
        "quality",
        &input,
        "--size",
        "64x48",
        "--max-depth",
        "1",
        "--orbit",
        "2",
        "--runs",
        "1",
    ]) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    let names = [
        "uniform-0",
        "uniform-1",
        "curvature",
        "pixel-error-2",
        "pixel-error-1",
        "pixel-error-0.5",
        "dicing-2",
        "dicing-1",
        "dicing-0.5",
    ];
    assert!(lines.len() >= names.len(), "{stdout}");
    let last = &lines[lines.len() - names.len()..];
    let mut silhouette = Vec::new();
    for (line, name) in last.iter().zip(names) {
        let f = fields(line);
        assert_eq!(f[0].0, name, "{line}");
        assert!(f[3].1 <= f[2].1, "p99 above max: {line}");
        silhouette.push((f[1].1, f[2].1));
    }
    // Uniform depth 0 has 6 quads = 12 triangles; depth 1 four times as many.
    assert_eq!((silhouette[0].0, silhouette[1].0), (12.0, 48.0), "{stdout}");
    assert!(silhouette[1].1 <= silhouette[0].1, "{stdout}");
}

#[test]
fn a_reference_that_is_not_deeper_is_refused() {
    let input = cube();
    let o = subdiv()
        .args([
            "bench",
            "quality",
            &input,
            "--max-depth",
            "3",
            "--reference-depth",
            "3",
        ])
        .output()
        .unwrap();
    assert_clean_failure(&o, "--reference-depth 3 is not deeper than --max-depth 3");
    let o = subdiv()
        .args(["bench", "quality", &input, "--orbit", "0"])
        .output()
        .unwrap();
    assert_clean_failure(&o, "--orbit must be at least 1");
}

#[test]
fn curvature_sweep_measures_every_combination_and_only_the_kinds_asked() {
    let input = cube();
    let Some(o) = run_ok(&[
        "bench",
        "quality",
        &input,
        "--size",
        "64x48",
        "--max-depth",
        "2",
        "--runs",
        "1",
        "--configs",
        "curvature",
        "--cone-aperture",
        "5,20",
        "--classifier",
        "0.2",
        "--projected-size",
        "1,4",
        "--projected-size",
        "off",
    ]) else {
        return;
    };
    let stdout = String::from_utf8_lossy(&o.stdout);
    let names: Vec<String> = stdout
        .lines()
        .filter(|l| l.starts_with("config="))
        .map(|l| fields(l)[0].0.clone())
        .collect();
    assert_eq!(
        names,
        [
            "curvature-cone5-eps0.2-size1-4",
            "curvature-cone5-eps0.2-sizeoff",
            "curvature-cone20-eps0.2-size1-4",
            "curvature-cone20-eps0.2-sizeoff",
        ],
        "{stdout}"
    );
}

#[test]
fn bad_curvature_parameters_are_refused() {
    let input = cube();
    for (flag, value, says) in [
        (
            "--cone-aperture",
            "0",
            "--cone-aperture 0: need an angle in (0, 180) degrees",
        ),
        (
            "--classifier",
            "1.5",
            "--classifier 1.5: need an epsilon in [0, 1)",
        ),
    ] {
        let o = subdiv()
            .args(["bench", "quality", &input, flag, value])
            .output()
            .unwrap();
        assert_clean_failure(&o, says);
    }
}

/// Dicing by pixels against the pixel-error mode on the helmet (semi-sharp creases of
/// sharpness 7, a boundary), small: at 4 px it draws at most 60 % of `pixel-error-1`'s
/// triangles with no more silhouette or shading error (here 2,843 against 9,376 triangles,
/// 0 px and 7.3° against 0 px and 8.2°). It fails with either rule of dicing's beyond Cycles
/// off: without the flatness rule the silhouette is 0.167 px off, without the one-sided
/// normals at a semi-sharp crease's cage vertices the shading p99 is 30.5°.
#[test]
fn dicing_beats_the_pixel_error_mode_on_the_helmet() {
    let input = shape("catmark_helmet.obj").to_string_lossy().into_owned();
    let Some(stdout) = depth4_run(&[
        &input,
        "--size",
        "320x240",
        "--configs",
        "pixel-error,dicing",
        "--dicing-rates",
        "4",
    ]) else {
        return;
    };
    let config = |name: &str| config_fields(&stdout, name);
    let (pixel, dicing) = (config("pixel-error-1"), config("dicing-4"));
    // Fields: triangles 1, silhouette max 2, shading p99 4.
    assert!(dicing[1].1 <= 0.6 * pixel[1].1, "{stdout}");
    assert!(dicing[2].1 <= pixel[2].1, "{stdout}");
    assert!(dicing[4].1 <= pixel[4].1, "{stdout}");
}

/// The paper's mode with its defaults on the paper's scene (helmet40 from `bench framerate`'s
/// first camera, 640×480, maximum depth 4): a picture no worse than uniform depth 3's, at most
/// half of uniform depth 4's triangles. With a projected-size bound of 1 px the far helmets are
/// coarsened until their shading is worse than uniform depth 3's, with more triangles.
#[test]
fn the_paper_mode_beats_uniform_depth_3_on_helmet40_at_half_of_depth_4() {
    let Some(stdout) = depth4_run(&[
        "--scene",
        "helmet40",
        "--size",
        "640x480",
        "--configs",
        "uniform,curvature",
    ]) else {
        return;
    };
    let config = |name: &str| config_fields(&stdout, name);
    let (paper, u3, u4) = (
        config("curvature"),
        config("uniform-3"),
        config("uniform-4"),
    );
    // Fields: triangles 1, silhouette max 2, shading p99 4.
    assert!(paper[2].1 <= u3[2].1, "{stdout}");
    assert!(paper[4].1 <= u3[4].1, "{stdout}");
    assert!(paper[1].1 <= 0.5 * u4[1].1, "{stdout}");
}
