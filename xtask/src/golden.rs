//! `cargo xtask golden [--bless] [--tolerance MEAN,P99] [SCENE...]`: golden-image regression.
//!
//! Every scene in [`SCENES`] is rendered headless on lavapipe by running the `subdiv render`
//! binary (so the command line is tested too) and compared with `fixtures/golden/<scene>.png`:
//! byte-exact by default, or within a mean / 99th-percentile error with `--tolerance`. A mismatch
//! writes `target/golden/<scene>.actual.png` and `<scene>.diff.png` and fails; `--bless` rewrites
//! the goldens instead. See `docs/golden.md`.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};
use subdiv_vk::golden::{self, Tolerance, Verdict};

use crate::vulkan;

/// One golden scene: `subdiv render INPUT ARGS --size 320x240 -o ...`.
pub struct Scene {
    /// File name of the golden image (`fixtures/golden/<name>.png`).
    pub name: &'static str,
    /// Input cage, relative to the workspace root.
    pub input: &'static str,
    /// Further `subdiv render` flags (camera, scheme, depth, shading).
    pub args: &'static [&'static str],
}

const fn scene(name: &'static str, input: &'static str, args: &'static [&'static str]) -> Scene {
    Scene { name, input, args }
}

/// Image size of every golden scene (small: quick to render, small to store).
pub const SIZE: &str = "320x240";

/// The golden scenes. Adding one is one line here plus `cargo xtask golden --bless NAME`.
#[rustfmt::skip]
pub const SCENES: &[Scene] = &[
    // Paper Fig. 9: a box with 6 faces and 8 infinitely sharp edges (top and bottom rims).
    scene("box_sharp_edges", "fixtures/scenes/box_8_sharp_edges.obj", &["--eye-relative", "1.1,1.0,1.6", "--depth", "3"]),
    scene("box_sharp_edges_wire", "fixtures/scenes/box_8_sharp_edges.obj", &["--eye-relative", "1.1,1.0,1.6", "--depth", "2", "--shading", "wire"]),
    scene("box_sharp_edges_adaptive", "fixtures/scenes/box_8_sharp_edges.obj", &["--eye-relative", "1.1,1.0,1.6", "--max-depth", "4", "--shading", "depth", "--wire-overlay"]),
    // Semi-sharp creases (sharpness 5 and 0.1) on a cube, and a row of crease variants.
    scene("cube_semisharp_creases", "fixtures/reference/shapes/catmark_cube_creases1.obj", &["--eye-relative", "1.2,1.5,1.2", "--up", "0,0,1", "--depth", "4"]),
    scene("single_crease_flat", "fixtures/reference/shapes/catmark_single_crease.obj", &["--eye-relative", "0.3,1.3,1.6", "--depth", "2", "--shading", "flat"]),
    // The embedded demo cage (Z up), smooth with silhouette lines.
    scene("pawn_silhouettes", "fixtures/reference/shapes/catmark_pawn.obj", &["--eye-relative", "1.5,-1.7,0.9", "--up", "0,0,1", "--depth", "3", "--silhouettes"]),
    // Loop limit surfaces: a sphere-like icosahedron and the bunny.
    scene("loop_icosahedron", "fixtures/reference/shapes/loop_icosahedron.obj", &["--scheme", "loop", "--eye-relative", "0.8,0.6,1.8", "--wire-overlay", "--depth", "2"]),
    scene("loop_bunny", "fixtures/meshes/tri_bunny_3k.obj", &["--scheme", "loop", "--depth", "1", "--eye-relative", "0.3,0.4,2.1"]),
    scene("loop_cubes_semisharp", "fixtures/reference/shapes/loop_cubes_semisharp.obj", &["--scheme", "loop", "--eye-relative", "0.6,1.2,1.6"]),
    // N-gons (triangles, pentagons, ...) and boundaries with corners.
    scene("nonquads_wire_overlay", "fixtures/reference/shapes/catmark_nonquads.obj", &["--eye-relative", "0.4,1.4,1.4", "--depth", "2", "--wire-overlay"]),
    scene("edgecorner_boundaries", "fixtures/reference/shapes/catmark_edgecorner.obj", &["--eye-relative", "0.4,1.4,1.4", "--depth", "2", "--wire-overlay"]),
    // Depth colours (uniform depth until adaptive depths land), and a creased torus.
    scene("helmet_depth", "fixtures/reference/shapes/catmark_helmet.obj", &["--eye-relative", "1.4,0.5,1.6", "--depth", "2", "--shading", "depth", "--wire-overlay"]),
    scene("torus_creases_silhouettes", "fixtures/reference/shapes/catmark_torus_creases0.obj", &["--eye-relative", "0.5,1.3,1.6", "--depth", "3", "--silhouettes"]),
    // Adaptive tessellation (Settgast et al. 2004). Fig. 11: depth-coloured wireframe of the
    // view-dependent depths.
    scene("pawn_adaptive_depth_wire", "fixtures/reference/shapes/catmark_pawn.obj", &["--eye-relative", "1.5,-1.7,0.9", "--up", "0,0,1", "--max-depth", "4", "--shading", "depth", "--wire-overlay"]),
    // Fig. 10: gap filling between depths, the simple fans against fans with the subdivided
    // shared edge (close-up of depth transitions on the helmet).
    scene("helmet_fans_simple", "fixtures/reference/shapes/catmark_helmet.obj", &["--eye-relative", "0.9,0.35,1.1", "--max-depth", "3", "--projected-size", "6,24", "--wire-overlay", "--simple-fans"]),
    scene("helmet_fans_subdivided", "fixtures/reference/shapes/catmark_helmet.obj", &["--eye-relative", "0.9,0.35,1.1", "--max-depth", "3", "--projected-size", "6,24", "--wire-overlay"]),
    // Fig. 10 as the paper draws it: one depth-1 patch amid depth-3 patches on a small bumped
    // 3 x 3 grid (fixed per-face depths), simple fans against fans with the subdivided edge.
    scene("grid_fans_simple", "fixtures/scenes/grid_3x3_bump.obj", &["--eye-relative", "0.1,0.75,0.4", "--face-depths", "3,3,3,3,1,3,3,3,3", "--shading", "depth", "--wire-overlay", "--simple-fans"]),
    scene("grid_fans_subdivided", "fixtures/scenes/grid_3x3_bump.obj", &["--eye-relative", "0.1,0.75,0.4", "--face-depths", "3,3,3,3,1,3,3,3,3", "--shading", "depth", "--wire-overlay"]),
    // Fig. 8: the back-face heuristic seen from a second camera: depths (and culling) chosen for
    // a camera below the pawn, the image taken from the side.
    scene("pawn_backface_second_camera", "fixtures/reference/shapes/catmark_pawn.obj", &["--eye-relative", "1.5,-1.7,0.9", "--up", "0,0,1", "--max-depth", "4", "--shading", "depth", "--wire-overlay", "--cull-camera-eye-relative", "-2.5,0.5,0.3"]),
    // Isenberg et al. 2003: DoI-driven adaptive Loop meshes (3 steps) on the teapot.
    // Fig. 3a (view angle), Fig. 3b (silhouette edges), Fig. 4 (static dihedral angle).
    scene("doi_view_angle_teapot", "fixtures/meshes/tri_teapot.obj", &["--split-nonmanifold", "--scheme", "loop", "--doi", "view-angle", "--eye-relative", "0,0.3,2.2", "--shading", "flat", "--wire-overlay"]),
    scene("doi_silhouette_teapot", "fixtures/meshes/tri_teapot.obj", &["--split-nonmanifold", "--scheme", "loop", "--doi", "silhouette", "--eye-relative", "0,0.3,2.2", "--shading", "flat", "--wire-overlay"]),
    scene("doi_dihedral_teapot", "fixtures/meshes/tri_teapot.obj", &["--split-nonmanifold", "--scheme", "loop", "--doi", "dihedral", "--eye-relative", "0,0.3,2.2", "--shading", "doi"]),
    // The vertex DoI (curvature at vertices), aggregated to faces by the average (§3), shaded
    // by the DoI.
    scene("doi_curvature_avg_bunny", "fixtures/meshes/tri_bunny_3k.obj", &["--scheme", "loop", "--doi", "curvature", "--aggregate", "avg", "--steps", "2", "--eye-relative", "0.3,0.4,2.1", "--shading", "doi", "--wire-overlay"]),
    // Fig. 9: the haptic DoI on the bunny (Clough-Tocher G1 error and one-side criterion).
    scene("doi_haptic_bunny", "fixtures/meshes/tri_bunny_3k.obj", &["--scheme", "loop", "--doi", "haptic", "--steps", "2", "--eye-relative", "0.3,0.4,2.1", "--shading", "flat", "--wire-overlay"]),
    // Fig. 10: the illustration focus DoI: two dominant objects of different interest (1 and
    // 0.5); the third, between them, gets the fading detail.
    scene("doi_focus_objects", "fixtures/scenes/focus_three_icosahedra.obj", &["--scheme", "loop", "--doi", "focus", "--focus", "focus=1", "--focus", "far=0.5", "--eye-relative", "0,0.5,1.6", "--shading", "flat", "--wire-overlay"]),
    // Fig. 12: the 40-instance scene, adaptive.
    scene("helmet40_adaptive", "", &["--scene", "helmet40", "--eye-relative", "0.2,0.6,1.4", "--max-depth", "3", "--shading", "depth"]),
];

/// Parsed `cargo xtask golden` arguments.
#[derive(Debug, Default)]
pub struct Options {
    /// Rewrite the goldens instead of comparing.
    pub bless: bool,
    /// Compare within this tolerance instead of exactly.
    pub tolerance: Option<Tolerance>,
    /// Only these scenes (all when empty).
    pub only: Vec<String>,
}

impl Options {
    /// Parses `[--bless] [--tolerance MEAN,P99] [SCENE...]`.
    pub fn parse(args: &[String]) -> Result<Options> {
        let mut o = Options::default();
        let mut it = args.iter();
        while let Some(a) = it.next() {
            match a.as_str() {
                "--bless" => o.bless = true,
                "--tolerance" => {
                    let v = it
                        .next()
                        .context("--tolerance needs MEAN,P99 (e.g. 0.5,8)")?;
                    o.tolerance = Some(parse_tolerance(v)?);
                }
                s if s.starts_with('-') => bail!(
                    "unknown flag {s}; usage: cargo xtask golden [--bless] [--tolerance MEAN,P99] [SCENE...]"
                ),
                s => {
                    if !SCENES.iter().any(|sc| sc.name == s) {
                        let names: Vec<_> = SCENES.iter().map(|sc| sc.name).collect();
                        bail!("unknown scene '{s}'; scenes: {}", names.join(", "));
                    }
                    o.only.push(s.to_string());
                }
            }
        }
        Ok(o)
    }
}

fn parse_tolerance(s: &str) -> Result<Tolerance> {
    let (m, p) = s
        .split_once(',')
        .with_context(|| format!("--tolerance '{s}' is not MEAN,P99"))?;
    let mean: f64 = m
        .trim()
        .parse()
        .with_context(|| format!("--tolerance: '{m}' is not a number"))?;
    let p99: f64 = p
        .trim()
        .parse()
        .with_context(|| format!("--tolerance: '{p}' is not a number"))?;
    if !(mean.is_finite() && p99.is_finite() && mean >= 0.0 && p99 >= 0.0) {
        bail!("--tolerance values must be finite and non-negative");
    }
    Ok(Tolerance { mean, p99 })
}

/// Builds `subdiv` (dev profile) and returns the path of the binary.
fn build_subdiv() -> Result<PathBuf> {
    crate::run({
        let mut c = crate::cargo();
        c.args(["build", "--quiet", "-p", "subdiv-cli"]);
        c
    })?;
    Ok(crate::target_dir()
        .join("debug")
        .join(format!("subdiv{}", std::env::consts::EXE_SUFFIX)))
}

/// Renders and compares (or blesses) the scenes; fails when any scene does not match.
pub fn run(root: &Path, options: &Options) -> Result<()> {
    vulkan::ensure_driver()?;
    let validation = Path::new(vulkan::VALIDATION_LAYER_MANIFEST).exists();
    let exe = build_subdiv()?;
    let expected_dir = root.join("fixtures/golden");
    let out_dir = root.join("target/golden");
    let rendered_dir = out_dir.join("rendered");
    std::fs::create_dir_all(&rendered_dir)
        .with_context(|| format!("cannot create {}", rendered_dir.display()))?;
    let mut failed = Vec::new();
    let scenes = SCENES
        .iter()
        .filter(|s| options.only.is_empty() || options.only.iter().any(|o| o == s.name));
    for scene in scenes {
        let png = rendered_dir.join(format!("{}.png", scene.name));
        for stale in [
            format!("{}.actual.png", scene.name),
            format!("{}.diff.png", scene.name),
        ] {
            let _ = std::fs::remove_file(out_dir.join(stale));
        }
        let mut cmd = Command::new(&exe);
        cmd.arg("render");
        if !scene.input.is_empty() {
            // An empty input means a built-in scene (`--scene` in the arguments).
            cmd.arg(root.join(scene.input));
        }
        cmd.args(scene.args).args(["--size", SIZE, "-o"]).arg(&png);
        vulkan::configure(&mut cmd, root);
        if validation {
            cmd.env("SUBDIV_VK_VALIDATION", "1");
        }
        let shown = format!(
            "subdiv render {} {} --size {SIZE}",
            scene.input,
            scene.args.join(" ")
        );
        let output = cmd
            .output()
            .with_context(|| format!("could not run {}", exe.display()))?;
        let stderr = String::from_utf8_lossy(&output.stderr);
        if !output.status.success() {
            bail!(
                "{}: `{shown}` failed ({}):\n{stderr}",
                scene.name,
                output.status
            );
        }
        if stderr.contains("subdiv-vk validation:") {
            eprintln!("{stderr}");
            failed.push(format!("{} (validation messages)", scene.name));
            continue;
        }
        let actual = subdiv_vk::read_png(&png)?;
        let expected = expected_dir.join(format!("{}.png", scene.name));
        if options.bless {
            golden::bless(&actual, &expected)?;
            println!(
                "golden {:<34} blessed -> {}",
                scene.name,
                expected.display()
            );
            continue;
        }
        match golden::compare_in(&actual, &expected, options.tolerance, &out_dir)? {
            Verdict::Identical => println!("golden {:<34} identical", scene.name),
            Verdict::WithinTolerance(s) => {
                println!(
                    "golden {:<34} within tolerance (mean {:.3}, p99 {:.1}, max {})",
                    scene.name, s.mean, s.p99, s.max
                )
            }
            Verdict::Mismatch {
                stats,
                reason,
                actual,
                diff,
            } => {
                println!(
                    "golden {:<34} MISMATCH: {reason} (mean {:.3}, p99 {:.1}, max {}, {} pixels differ)\n    actual: {}\n    diff:   {}",
                    scene.name,
                    stats.mean,
                    stats.p99,
                    stats.max,
                    stats.differing_pixels,
                    actual.display(),
                    diff.map_or_else(|| "-".into(), |d| d.display().to_string()),
                );
                failed.push(scene.name.to_string());
            }
            Verdict::MissingExpected { actual } => {
                println!(
                    "golden {:<34} MISSING {} (actual: {}; accept with `cargo xtask golden --bless {}`)",
                    scene.name,
                    expected.display(),
                    actual.display(),
                    scene.name
                );
                failed.push(scene.name.to_string());
            }
        }
    }
    if !failed.is_empty() {
        bail!(
            "{} golden scene(s) failed: {}; review target/golden/*.diff.png, and if the change is intended \
             run `cargo xtask golden --bless` (see docs/golden.md)",
            failed.len(),
            failed.join(", ")
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_are_unique_and_exist() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
        let mut names: Vec<_> = SCENES.iter().map(|s| s.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), SCENES.len(), "duplicate scene names");
        assert!(SCENES.len() >= 12);
        for s in SCENES {
            assert!(
                (s.input.is_empty() && s.args.contains(&"--scene")) || root.join(s.input).is_file(),
                "{}: missing input {}",
                s.name,
                s.input
            );
            assert!(
                !s.args.contains(&"-o") && !s.args.contains(&"--size"),
                "{}: size and output are set by xtask",
                s.name
            );
        }
    }

    #[test]
    fn parses_arguments() {
        let args = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let o = Options::parse(&args(&["--bless", "loop_bunny"])).unwrap();
        assert!(o.bless && o.tolerance.is_none() && o.only == ["loop_bunny"]);
        let o = Options::parse(&args(&["--tolerance", "0.5,8"])).unwrap();
        assert_eq!(
            o.tolerance,
            Some(Tolerance {
                mean: 0.5,
                p99: 8.0
            })
        );
        assert!(Options::parse(&args(&["--tolerance", "0.5"])).is_err());
        assert!(Options::parse(&args(&["--tolerance", "-1,2"])).is_err());
        assert!(Options::parse(&args(&["no_such_scene"])).is_err());
        assert!(Options::parse(&args(&["--fast"])).is_err());
    }
}
