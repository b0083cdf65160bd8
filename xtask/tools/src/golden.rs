//! `cargo xtask golden [--bless] [--exact|--perceptual|--tolerance MEAN,P99] [SCENE...]`: golden-image regression.
//!
//! Every scene in [`SCENES`] is rendered headless on lavapipe by running the `subdiv render`
//! binary (so the command line is tested too) and compared with `fixtures/golden/<scene>.png`:
//! byte-exact on the pinned Mesa ([`vulkan::PINNED_MESA`], Debian 12), perceptually on any other
//! Mesa (mean NVIDIA FLIP error within the scene's [`Scene::flip`] threshold), or within a mean /
//! 99th-percentile channel error with `--tolerance`. A mismatch writes
//! `target/golden/<scene>.actual.png` and `<scene>.diff.png` and fails; `--bless` rewrites the
//! goldens instead. See `docs/golden.md`. FLIP (C++) is compiled only with the `flip` feature,
//! which xtask enables when the comparison is perceptual; without it a perceptual comparison
//! fails before rendering, naming the command.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, bail};
#[cfg(feature = "flip")]
use image::RgbaImage;
use subdiv_vk::golden::{self, Tolerance, Verdict};

use xtask::vulkan;

/// One golden scene: `subdiv render INPUT ARGS --size 320x240 -o ...`.
pub struct Scene {
    /// File name of the golden image (`fixtures/golden/<name>.png`).
    pub name: &'static str,
    /// Input cage, relative to the workspace root.
    pub input: &'static str,
    /// Further `subdiv render` flags (camera, scheme, depth, shading).
    pub args: &'static [&'static str],
    /// Largest mean FLIP error (0..1) accepted off the pinned Mesa ([`DEFAULT_FLIP`] unless the
    /// scene sets its own with [`Scene::flip`]).
    #[cfg_attr(not(feature = "flip"), allow(dead_code))]
    pub flip: f32,
}

/// The mean FLIP error a scene may show on another Mesa version: well under what a visible
/// change (a moved edge, a different shade) gives, above rasterization and LLVM rounding.
pub const DEFAULT_FLIP: f32 = 0.01;

const fn scene(name: &'static str, input: &'static str, args: &'static [&'static str]) -> Scene {
    Scene {
        name,
        input,
        args,
        flip: DEFAULT_FLIP,
    }
}

impl Scene {
    /// This scene with its own FLIP threshold (e.g. a dense wireframe whose lines shift by a
    /// pixel between Mesa versions).
    #[allow(dead_code)]
    const fn flip(self, flip: f32) -> Scene {
        Scene { flip, ..self }
    }
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
    // A primvar drawn: the pawn's vertex colours (displayColor, from make_pawn_colors.py).
    scene("pawn_display_color", "fixtures/scenes/pawn_colors.obj", &["--eye-relative", "1.5,-1.7,0.9", "--up", "0,0,1", "--depth", "3", "--shading", "primvar:displayColor"]),
    // Loop limit surfaces: a sphere-like icosahedron and the bunny.
    scene("loop_icosahedron", "fixtures/reference/shapes/loop_icosahedron.obj", &["--scheme", "loop", "--eye-relative", "0.8,0.6,1.8", "--wire-overlay", "--depth", "2"]),
    scene("loop_bunny", "fixtures/meshes/tri_bunny_3k.obj", &["--scheme", "loop", "--depth", "1", "--eye-relative", "0.3,0.4,2.1"]),
    scene("loop_cubes_semisharp", "fixtures/reference/shapes/loop_cubes_semisharp.obj", &["--scheme", "loop", "--eye-relative", "0.6,1.2,1.6", "--depth", "3"]),
    // N-gons (triangles, pentagons, ...) and boundaries with corners.
    scene("nonquads_wire_overlay", "fixtures/reference/shapes/catmark_nonquads.obj", &["--eye-relative", "0.4,1.4,1.4", "--depth", "2", "--wire-overlay"]),
    scene("edgecorner_boundaries", "fixtures/reference/shapes/catmark_edgecorner.obj", &["--eye-relative", "0.4,1.4,1.4", "--depth", "2", "--wire-overlay"]),
    // Depth colours (uniform depth until adaptive depths land), and a creased torus.
    scene("helmet_depth", "fixtures/reference/shapes/catmark_helmet.obj", &["--eye-relative", "1.4,0.5,1.6", "--depth", "2", "--shading", "depth", "--wire-overlay"]),
    scene("torus_creases_silhouettes", "fixtures/reference/shapes/catmark_torus_creases0.obj", &["--eye-relative", "0.5,1.3,1.6", "--depth", "3", "--silhouettes"]),
    // Adaptive tessellation (Settgast et al. 2004). Fig. 11: depth-coloured wireframe of the
    // view-dependent depths; the one scene drawn at one sample per pixel (every other at the
    // default, 4 on lavapipe).
    scene("pawn_adaptive_depth_wire", "fixtures/reference/shapes/catmark_pawn.obj", &["--eye-relative", "1.5,-1.7,0.9", "--up", "0,0,1", "--max-depth", "4", "--shading", "depth", "--wire-overlay", "--samples", "1"]),
    // Fig. 10: gap filling between depths, the simple fans against fans with the subdivided
    // shared edge (close-up of depth transitions on the helmet).
    scene("helmet_fans_simple", "fixtures/reference/shapes/catmark_helmet.obj", &["--eye-relative", "0.9,0.35,1.1", "--max-depth", "3", "--projected-size", "6,24", "--wire-overlay", "--simple-fans"]),
    scene("helmet_fans_subdivided", "fixtures/reference/shapes/catmark_helmet.obj", &["--eye-relative", "0.9,0.35,1.1", "--max-depth", "3", "--projected-size", "6,24", "--wire-overlay"]),
    // Fig. 10 as the paper draws it: one depth-1 patch amid depth-3 patches on a small bumped
    // 3 x 3 grid (fixed per-face depths), simple fans against fans with the subdivided edge.
    scene("grid_fans_simple", "fixtures/scenes/grid_3x3_bump.obj", &["--eye-relative", "0.1,0.75,0.4", "--face-depths", "3,3,3,3,1,3,3,3,3", "--shading", "depth", "--wire-overlay", "--simple-fans"]),
    scene("grid_fans_subdivided", "fixtures/scenes/grid_3x3_bump.obj", &["--eye-relative", "0.1,0.75,0.4", "--face-depths", "3,3,3,3,1,3,3,3,3", "--shading", "depth", "--wire-overlay"]),
    // The bilinear scheme adaptively: twisted patches (and n-gons' level-1 quads) refined until
    // their own normals fit the cone, flat ones drawn as themselves, fans between depths.
    scene("nonquads_bilinear_adaptive", "fixtures/reference/shapes/catmark_nonquads.obj", &["--scheme", "bilinear", "--eye-relative", "0.4,1.4,1.4", "--max-depth", "4", "--shading", "depth", "--wire-overlay"]),
    // Dicing by pixels: every cage edge at the rate its limit curve's length (and bend) on
    // screen asks for at 12 px, semi-sharp creases drawn with each side's normal.
    scene("helmet_dicing_12px", "fixtures/reference/shapes/catmark_helmet.obj", &["--eye-relative", "1.4,0.5,1.6", "--dicing-rate", "12", "--wire-overlay"]),
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
    // Colour legends (`--legend`): the adaptive depths of Fig. 11 and the dihedral DoI heat map.
    scene("pawn_adaptive_depth_legend", "fixtures/reference/shapes/catmark_pawn.obj", &["--eye-relative", "1.5,-1.7,0.9", "--up", "0,0,1", "--max-depth", "4", "--shading", "depth", "--legend"]),
    scene("doi_dihedral_teapot_legend", "fixtures/meshes/tri_teapot.obj", &["--split-nonmanifold", "--scheme", "loop", "--doi", "dihedral", "--eye-relative", "0,0.3,2.2", "--shading", "doi", "--legend"]),
    // Adaptive Loop: the icosahedron's triangle patches at view-dependent
    // depths (front 3, silhouette 4, back 0), joined by triangle fans, depth-coloured.
    scene("loop_icosahedron_adaptive_depth", "fixtures/reference/shapes/loop_icosahedron.obj", &["--scheme", "loop", "--eye-relative", "0.8,0.6,1.8", "--max-depth", "4", "--projected-size", "2,8", "--shading", "depth", "--wire-overlay"]),
    // Fig. 12: the 40-instance scene, adaptive.
    scene("helmet40_adaptive", "", &["--scene", "helmet40", "--eye-relative", "0.2,0.6,1.4", "--max-depth", "3", "--shading", "depth"]),
];

/// How renders are compared with the goldens.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Mode {
    /// Byte-exact on the pinned Mesa, perceptual (FLIP) elsewhere.
    #[default]
    Auto,
    /// Byte-exact (`--exact`).
    Exact,
    /// Mean FLIP error within each scene's threshold (`--perceptual`).
    Perceptual,
    /// Mean and 99th-percentile channel error (`--tolerance MEAN,P99`).
    Tolerance(Tolerance),
}

/// Parsed `cargo xtask golden` arguments.
#[derive(Debug, Default)]
pub struct Options {
    /// Rewrite the goldens instead of comparing.
    pub bless: bool,
    /// How to compare.
    pub mode: Mode,
    /// Only these scenes (all when empty).
    pub only: Vec<String>,
}

const USAGE: &str = "usage: cargo xtask golden [--bless] [--exact | --perceptual | --tolerance MEAN,P99] [SCENE...]";

impl Options {
    /// Parses `[--bless] [--exact | --perceptual | --tolerance MEAN,P99] [SCENE...]`.
    pub fn parse(args: &[String]) -> Result<Options> {
        let mut o = Options::default();
        let mut it = args.iter();
        while let Some(a) = it.next() {
            match a.as_str() {
                "--bless" => o.bless = true,
                "--exact" | "--perceptual" | "--tolerance" if o.mode != Mode::Auto => {
                    bail!("give one of --exact, --perceptual and --tolerance; {USAGE}")
                }
                "--exact" => o.mode = Mode::Exact,
                "--perceptual" => o.mode = Mode::Perceptual,
                "--tolerance" => {
                    let v = it
                        .next()
                        .context("--tolerance needs MEAN,P99 (e.g. 0.5,8)")?;
                    o.mode = Mode::Tolerance(parse_tolerance(v)?);
                }
                s if s.starts_with('-') => bail!("unknown flag {s}; {USAGE}"),
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

/// Renders and compares (or blesses) the scenes; fails when any scene does not match.
pub fn run(root: &Path, options: &Options) -> Result<()> {
    xtask::step(if options.bless {
        "golden images (blessing)"
    } else {
        "golden images"
    });
    vulkan::ensure_driver()?;
    let validation = Path::new(vulkan::VALIDATION_LAYER_MANIFEST).exists()
        || std::env::var(subdiv_vk::REQUIRE_VALIDATION_ENV).as_deref() == Ok("1");
    let exe = xtask::build_subdiv("dev")?;
    let mode = match options.mode {
        Mode::Auto => {
            let mesa = vulkan::mesa_version();
            if mesa.as_deref() == Some(vulkan::PINNED_MESA) {
                eprintln!(
                    "xtask: Mesa {} (pinned): byte-exact comparison",
                    vulkan::PINNED_MESA
                );
                Mode::Exact
            } else {
                eprintln!(
                    "xtask: Mesa {} is not the pinned {}: perceptual comparison (mean FLIP error \
                     within each scene's threshold; --exact to demand identical bytes)",
                    mesa.as_deref().unwrap_or("(version unknown)"),
                    vulkan::PINNED_MESA
                );
                Mode::Perceptual
            }
        }
        m => m,
    };
    if mode == Mode::Perceptual && !options.bless && !cfg!(feature = "flip") {
        bail!(
            "the perceptual comparison needs NVIDIA FLIP, and xtask-tools was built without its \
             `flip` feature: run `cargo xtask golden` (which enables it when needed)"
        );
    }
    let rendered_dir = root.join("target/golden/rendered");
    std::fs::create_dir_all(&rendered_dir)
        .with_context(|| format!("cannot create {}", rendered_dir.display()))?;
    let scenes: Vec<&Scene> = SCENES
        .iter()
        .filter(|s| options.only.is_empty() || options.only.iter().any(|o| o == s.name))
        .collect();
    let bar = crate::progress(scenes.len() as u64, "golden");
    let result = render_and_compare(root, &exe, &scenes, (mode, options.bless), validation, &bar);
    bar.finish_and_clear();
    let failed = result?;
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

/// FLIP statistics of a render against its golden.
#[cfg(feature = "flip")]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlipStats {
    /// Mean FLIP error over all pixels (0 = identical, 1 = as different as can be).
    pub mean: f32,
    /// Largest per-pixel FLIP error.
    pub max: f32,
}

/// Runs NVIDIA's FLIP on two images of the same size (alpha ignored; the renders are opaque) and
/// returns the statistics and the error map coloured with the magma table.
#[cfg(feature = "flip")]
pub fn flip(actual: &RgbaImage, expected: &RgbaImage) -> (FlipStats, RgbaImage) {
    let rgb = |img: &RgbaImage| {
        let data: Vec<u8> = img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect();
        nv_flip::FlipImageRgb8::with_data(img.width(), img.height(), &data)
    };
    let error = nv_flip::flip(
        rgb(expected),
        rgb(actual),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let pool = nv_flip::FlipPool::from_image(&error);
    let stats = FlipStats {
        mean: pool.mean(),
        max: pool.max_value(),
    };
    let map = error.apply_color_lut(&nv_flip::magma_lut());
    let map = RgbaImage::from_fn(map.width(), map.height(), {
        let data = map.to_vec();
        let w = map.width() as usize;
        move |x, y| {
            let i = 3 * (y as usize * w + x as usize);
            image::Rgba([data[i], data[i + 1], data[i + 2], 255])
        }
    });
    (stats, map)
}

/// Compares one scene perceptually (mean FLIP within [`Scene::flip`]); prints the verdict,
/// writes `<scene>.actual.png` and the FLIP map as `<scene>.diff.png` on failure, and returns
/// whether it passed.
#[cfg(feature = "flip")]
fn compare_perceptual(
    scene: &Scene,
    actual: &RgbaImage,
    expected_path: &Path,
    out_dir: &Path,
) -> Result<bool> {
    let actual_path = out_dir.join(format!("{}.actual.png", scene.name));
    if !expected_path.exists() {
        subdiv_vk::write_png(&actual_path, actual)?;
        println!(
            "golden {:<34} MISSING {} (actual: {}; accept with `cargo xtask golden --bless {}`)",
            scene.name,
            expected_path.display(),
            actual_path.display(),
            scene.name
        );
        return Ok(false);
    }
    let expected = subdiv_vk::read_png(expected_path)?;
    if expected.as_raw() == actual.as_raw() {
        println!("golden {:<34} identical", scene.name);
        return Ok(true);
    }
    if expected.dimensions() != actual.dimensions() {
        subdiv_vk::write_png(&actual_path, actual)?;
        println!(
            "golden {:<34} MISMATCH: size {:?} differs from expected {:?}\n    actual: {}",
            scene.name,
            actual.dimensions(),
            expected.dimensions(),
            actual_path.display()
        );
        return Ok(false);
    }
    let (stats, map) = flip(actual, &expected);
    if stats.mean <= scene.flip {
        println!(
            "golden {:<34} within FLIP threshold (mean {:.4} <= {}, max {:.3})",
            scene.name, stats.mean, scene.flip, stats.max
        );
        return Ok(true);
    }
    let diff_path = out_dir.join(format!("{}.diff.png", scene.name));
    subdiv_vk::write_png(&actual_path, actual)?;
    subdiv_vk::write_png(&diff_path, &map)?;
    println!(
        "golden {:<34} MISMATCH: mean FLIP {:.4} (allowed {}), max {:.3}\n    actual: {}\n    diff:   {} (FLIP error map)",
        scene.name,
        stats.mean,
        scene.flip,
        stats.max,
        actual_path.display(),
        diff_path.display()
    );
    Ok(false)
}

/// Renders each scene and compares it with its golden (or blesses it); returns the failures.
fn render_and_compare(
    root: &Path,
    exe: &Path,
    scenes: &[&Scene],
    (mode, bless): (Mode, bool),
    validation: bool,
    bar: &indicatif::ProgressBar,
) -> Result<Vec<String>> {
    let expected_dir = root.join("fixtures/golden");
    let out_dir = root.join("target/golden");
    let rendered_dir = out_dir.join("rendered");
    let mut failed = Vec::new();
    for scene in scenes {
        bar.set_message(scene.name);
        bar.inc(1);
        let png = rendered_dir.join(format!("{}.png", scene.name));
        for stale in [
            format!("{}.actual.png", scene.name),
            format!("{}.diff.png", scene.name),
        ] {
            let _ = std::fs::remove_file(out_dir.join(stale));
        }
        let mut cmd = Command::new(exe);
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
            bar.suspend(|| eprintln!("{stderr}"));
            failed.push(format!("{} (validation messages)", scene.name));
            continue;
        }
        let actual = subdiv_vk::read_png(&png)?;
        let expected = expected_dir.join(format!("{}.png", scene.name));
        if bless {
            golden::bless(&actual, &expected)?;
            bar.suspend(|| {
                println!(
                    "golden {:<34} blessed -> {}",
                    scene.name,
                    expected.display()
                )
            });
            continue;
        }
        #[cfg(feature = "flip")]
        if mode == Mode::Perceptual {
            if !bar.suspend(|| compare_perceptual(scene, &actual, &expected, &out_dir))? {
                failed.push(scene.name.to_string());
            }
            continue;
        }
        let tolerance = match mode {
            Mode::Tolerance(t) => Some(t),
            _ => None,
        };
        match golden::compare_in(&actual, &expected, tolerance, &out_dir)? {
            Verdict::Identical => bar.suspend(|| println!("golden {:<34} identical", scene.name)),
            Verdict::WithinTolerance(s) => bar.suspend(|| {
                println!(
                    "golden {:<34} within tolerance (mean {:.3}, p99 {:.1}, max {})",
                    scene.name, s.mean, s.p99, s.max
                )
            }),
            Verdict::Mismatch {
                stats,
                reason,
                actual,
                diff,
            } => {
                bar.suspend(|| println!(
                    "golden {:<34} MISMATCH: {reason} (mean {:.3}, p99 {:.1}, max {}, {} pixels differ)\n    actual: {}\n    diff:   {}",
                    scene.name,
                    stats.mean,
                    stats.p99,
                    stats.max,
                    stats.differing_pixels,
                    actual.display(),
                    diff.map_or_else(|| "-".into(), |d| d.display().to_string()),
                ));
                failed.push(scene.name.to_string());
            }
            Verdict::MissingExpected { actual } => {
                bar.suspend(|| println!(
                    "golden {:<34} MISSING {} (actual: {}; accept with `cargo xtask golden --bless {}`)",
                    scene.name,
                    expected.display(),
                    actual.display(),
                    scene.name
                ));
                failed.push(scene.name.to_string());
            }
        }
    }
    Ok(failed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_are_unique_and_exist() {
        let root = xtask::root();
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
        assert!(o.bless && o.mode == Mode::Auto && o.only == ["loop_bunny"]);
        let o = Options::parse(&args(&["--tolerance", "0.5,8"])).unwrap();
        assert_eq!(
            o.mode,
            Mode::Tolerance(Tolerance {
                mean: 0.5,
                p99: 8.0
            })
        );
        assert_eq!(
            Options::parse(&args(&["--exact"])).unwrap().mode,
            Mode::Exact
        );
        assert_eq!(
            Options::parse(&args(&["--perceptual"])).unwrap().mode,
            Mode::Perceptual
        );
        assert!(Options::parse(&args(&["--exact", "--perceptual"])).is_err());
        assert!(Options::parse(&args(&["--tolerance", "0.5"])).is_err());
        assert!(Options::parse(&args(&["--tolerance", "-1,2"])).is_err());
        assert!(Options::parse(&args(&["no_such_scene"])).is_err());
        assert!(Options::parse(&args(&["--fast"])).is_err());
    }

    /// Like a render: a flat background and a shaded object (a smooth gradient) at `shift`.
    #[cfg(feature = "flip")]
    fn picture(shift: u32) -> RgbaImage {
        RgbaImage::from_fn(160, 120, |x, y| {
            let inside = (50 + shift..110 + shift).contains(&x) && (30..90).contains(&y);
            if inside {
                let g = (90 + x + y / 2) as u8;
                image::Rgba([g, g / 2 + 40, 60, 255])
            } else {
                image::Rgba([40, 40, 48, 255])
            }
        })
    }

    /// `picture(0)` with the object's red and green raised by 1 on every `every`-th pixel
    /// (shading rounding as another Mesa/LLVM version gives it).
    #[cfg(feature = "flip")]
    fn rounded(every: usize) -> RgbaImage {
        let mut n = picture(0);
        for (i, p) in n.pixels_mut().enumerate() {
            if i % every == 0 && p[2] == 60 {
                p[0] += 1;
                p[1] += 1;
            }
        }
        n
    }

    /// With the `flip` feature: `cargo test -p xtask-tools --features flip`.
    #[cfg(feature = "flip")]
    #[test]
    fn flip_tells_noise_from_a_change() {
        let a = picture(0);
        let (same, map) = flip(&a, &a);
        assert_eq!(same.mean, 0.0);
        assert_eq!(map.dimensions(), a.dimensions());
        // Rounding-sized differences (1/255 in the shading) stay under the threshold...
        let (n, _) = flip(&rounded(3), &a);
        assert!(n.mean > 0.0 && n.mean < DEFAULT_FLIP / 2.0, "{n:?}");
        // ...an object moved by two pixels is over it.
        let (moved, _) = flip(&picture(2), &a);
        assert!(moved.mean > DEFAULT_FLIP, "{moved:?}");
    }

    #[test]
    fn every_scene_has_a_threshold() {
        for s in SCENES {
            assert!(s.flip > 0.0 && s.flip < 0.1, "{}: {}", s.name, s.flip);
        }
    }
}
