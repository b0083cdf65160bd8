//! `subdiv render` and `subdiv view` end to end: images, EXR, errors without panics, no driver.
//!
//! With the Khronos validation layer installed, every render runs with it and fails on any
//! validation message. Without a Vulkan driver the render tests print a note and pass, unless
//! `SUBDIV_VK_REQUIRE_DRIVER=1` (set by `cargo xtask test`). The window test runs under the
//! X server in `DISPLAY`, or starts one with `xvfb-run`; without either it prints a note and
//! passes, unless `SUBDIV_VK_REQUIRE_DISPLAY=1`.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_clean_failure, root, run_ok, stderr, subdiv, tmp, view_command};
use subdiv_vk::{read_exr, read_png};

fn box_obj() -> PathBuf {
    root().join("fixtures/scenes/box_8_sharp_edges.obj")
}

fn pixel(img: &subdiv_vk::image::RgbaImage, x: u32, y: u32) -> [u8; 4] {
    img.get_pixel(x, y).0
}

#[test]
fn render_writes_a_png_of_the_requested_size_with_the_surface_in_the_centre() {
    let out = tmp("box.png");
    let input = box_obj();
    let Some(o) = run_ok(&[
        "render",
        input.to_str().unwrap(),
        "--size",
        "160x120",
        "-o",
        out.to_str().unwrap(),
    ]) else {
        return;
    };
    assert!(String::from_utf8_lossy(&o.stdout).contains("rendered"));
    let img = read_png(&out).unwrap();
    assert_eq!(img.dimensions(), (160, 120));
    assert_eq!(
        pixel(&img, 0, 0),
        [255, 255, 255, 255],
        "corner is background"
    );
    let c = pixel(&img, 80, 60);
    assert!(
        c[..3] != [255, 255, 255] && c[0] == c[1] && c[1] == c[2],
        "centre {c:?} is not the grey surface"
    );
}

#[test]
fn exr_holds_depth_normals_and_the_subdivision_depth() {
    let (png, exr) = (tmp("exr.png"), tmp("exr.exr"));
    let input = box_obj();
    let args = [
        "render",
        input.to_str().unwrap(),
        "--depth",
        "2",
        "--size",
        "64x48",
        "-o",
        png.to_str().unwrap(),
    ];
    let Some(_) = run_ok(&[&args[..], &["--exr", exr.to_str().unwrap()]].concat()) else {
        return;
    };
    let (w, h, channels) = read_exr(&exr).unwrap();
    assert_eq!((w, h), (64, 48));
    let centre = (24 * 64 + 32) as usize;
    let channel = |n: &str| {
        &channels
            .iter()
            .find(|c| c.name == n)
            .unwrap_or_else(|| panic!("no channel {n}"))
            .samples
    };
    assert_eq!(
        channel("S")[centre],
        2.0,
        "per-vertex scalar is the subdivision depth"
    );
    let z = channel("Z")[centre];
    assert!(z.is_finite() && z > 0.0, "linear depth {z}");
    let n = [
        channel("N.X")[centre],
        channel("N.Y")[centre],
        channel("N.Z")[centre],
    ];
    let len = n.iter().map(|v| v * v).sum::<f32>().sqrt();
    assert!((len - 1.0).abs() < 0.05, "normal {n:?}");
}

#[test]
fn shadings_and_silhouettes_change_the_image() {
    let input = box_obj();
    let base = [
        "render",
        input.to_str().unwrap(),
        "--depth",
        "2",
        "--size",
        "96x72",
    ];
    let mut images = Vec::new();
    for (name, extra) in [
        ("smooth", &[][..]),
        ("flat", &["--shading", "flat"][..]),
        ("wire", &["--shading", "wire"][..]),
        ("depth", &["--shading", "depth"][..]),
        ("silhouettes", &["--silhouettes"][..]),
        ("overlay", &["--wire-overlay"][..]),
    ] {
        let out = tmp(&format!("shading-{name}.png"));
        if run_ok(&[&base[..], extra, &["-o", out.to_str().unwrap()]].concat()).is_none() {
            return;
        }
        images.push((name, read_png(&out).unwrap()));
    }
    for i in 0..images.len() {
        for j in i + 1..images.len() {
            assert!(
                images[i].1 != images[j].1,
                "{} and {} render the same image",
                images[i].0,
                images[j].0
            );
        }
    }
    let has = |img: &subdiv_vk::image::RgbaImage, f: &dyn Fn([u8; 4]) -> bool| {
        img.pixels().any(|p| f(p.0))
    };
    let red = |p: [u8; 4]| p[0] > 150 && p[1] < 80 && p[2] < 80;
    assert!(has(&images[4].1, &red), "silhouette lines are red");
    assert!(!has(&images[0].1, &red));
    let coloured = |p: [u8; 4]| p[0].abs_diff(p[1]) > 30 || p[1].abs_diff(p[2]) > 30;
    assert!(has(&images[3].1, &coloured), "depth shading is coloured");
    assert!(!has(&images[0].1, &coloured), "smooth shading is grey");
}

#[test]
fn missing_and_invalid_inputs_fail_cleanly() {
    let out = tmp("never.png");
    let o = subdiv()
        .args([
            "render",
            "/nonexistent/cage.obj",
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_clean_failure(&o, "/nonexistent/cage.obj");
    let bad = tmp("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    for cmd in ["render", "view"] {
        let o = subdiv()
            .args([cmd, bad.to_str().unwrap(), "-o", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert_clean_failure(&o, &format!("{}:4:", bad.display()));
    }
    let o = subdiv()
        .args([
            "render",
            box_obj().to_str().unwrap(),
            "--shading",
            "doi",
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_clean_failure(&o, "--shading doi needs --doi");
    let quads = box_obj();
    let o = subdiv()
        .args([
            "render",
            quads.to_str().unwrap(),
            "--scheme",
            "loop",
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_clean_failure(&o, "box_8_sharp_edges.obj");
    assert!(!out.exists());
}

#[test]
fn no_vulkan_driver_names_the_package_to_install() {
    let out = tmp("nodriver.png");
    let o = subdiv()
        .env("VK_DRIVER_FILES", "/nonexistent.json")
        .env("VK_ICD_FILENAMES", "/nonexistent.json")
        .env_remove("SUBDIV_VK_VALIDATION")
        .args([
            "render",
            box_obj().to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_clean_failure(&o, "mesa-vulkan-drivers");
    assert!(!out.exists());
}

/// `subdiv view --screenshot-after 5` shows exactly what `subdiv render` draws, silhouettes,
/// wireframe and depth colours included.
#[test]
fn view_screenshot_equals_render() {
    if view_command().is_none() {
        return;
    }
    let input = box_obj();
    let flags = [
        "--depth",
        "2",
        "--size",
        "200x150",
        "--shading",
        "depth",
        "--wire-overlay",
        "--silhouettes",
    ];
    let rendered = tmp("view-render.png");
    let Some(_) = run_ok(
        &[
            &["render", input.to_str().unwrap()][..],
            &flags,
            &["-o", rendered.to_str().unwrap()],
        ]
        .concat(),
    ) else {
        return;
    };
    let shot = tmp("view-shot.png");
    let o = view_command()
        .unwrap()
        .args(["view", input.to_str().unwrap()])
        .args(flags)
        .args([
            "--screenshot-after",
            "5",
            "--no-hud",
            "-o",
            shot.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = stderr(&o);
    assert!(o.status.success(), "subdiv view failed:\n{err}");
    assert!(
        !err.contains("subdiv-vk validation:"),
        "validation messages:\n{err}"
    );
    assert!(String::from_utf8_lossy(&o.stdout).contains("5 frames"));
    let (a, b) = (read_png(&shot).unwrap(), read_png(&rendered).unwrap());
    assert_eq!(a.dimensions(), (200, 150));
    assert!(a == b, "view screenshot differs from subdiv render");
}

#[test]
fn doi_meshes_render_with_doi_shading() {
    let teapot = root().join("fixtures/meshes/tri_teapot.obj");
    let out = tmp("doi.png");
    let Some(o) = run_ok(&[
        "render",
        teapot.to_str().unwrap(),
        "--split-nonmanifold",
        "--scheme",
        "loop",
        "--doi",
        "silhouette",
        "--eye-relative",
        "0,0.3,2.2",
        "--shading",
        "doi",
        "--size",
        "160x120",
        "-o",
        out.to_str().unwrap(),
    ]) else {
        return;
    };
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    // Fewer triangles than three uniform Loop steps (992 * 64).
    let after: usize = text
        .split("-> ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert!(after > 992 && after < 992 * 64, "{text}");
    let img = subdiv_vk::read_png(&out).unwrap();
    let centre = pixel(&img, 80, 60);
    assert_ne!(centre, pixel(&img, 0, 0), "the teapot is drawn");
    // DoI shading without a DoI is a clear error.
    let o = subdiv()
        .args([
            "render",
            teapot.to_str().unwrap(),
            "--split-nonmanifold",
            "--scheme",
            "loop",
            "--shading",
            "doi",
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_clean_failure(&o, "--shading doi needs --doi");
}

/// `render` refuses the DoI options (haptic interaction point, aggregation, skeleton) without
/// the DoI that uses them, and a scheme other than Loop's with a DoI.
fn doi_options_without_their_doi_are_refused(bunny: &str, out: &Path) {
    // The DoI-driven mesh is Loop's: another scheme named with it is refused, not drawn as Loop.
    for scheme in ["catmull-clark", "bilinear"] {
        let o = subdiv()
            .args([
                "render",
                bunny,
                "--scheme",
                scheme,
                "--doi",
                "view-angle",
                "-o",
            ])
            .arg(out)
            .output()
            .unwrap();
        let want = format!("--scheme {scheme} cannot go with it");
        assert_clean_failure(&o, &want);
    }
    // As is a stage that declares another scheme; a stage that declares Loop is drawn.
    let o = subdiv()
        .arg("render")
        .arg(root().join("fixtures/usd/cube_uv.usda"))
        .args(["--doi", "view-angle", "-o"])
        .arg(out)
        .output()
        .unwrap();
    assert_clean_failure(
        &o,
        "the stage's subdivisionScheme (catmull-clark) cannot go with it",
    );
    let o = subdiv()
        .arg("render")
        .arg(root().join("fixtures/usd/tetra_loop.usda"))
        .args(["--doi", "view-angle", "-o"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The options without their DoI are refused.
    let o = subdiv()
        .args(["render", bunny, "--scheme", "loop", "--hip", "0,0,0", "-o"])
        .arg(out)
        .output()
        .unwrap();
    assert_clean_failure(&o, "--hip needs --doi haptic");
    let o = subdiv()
        .args([
            "render",
            bunny,
            "--scheme",
            "loop",
            "--aggregate",
            "avg",
            "-o",
        ])
        .arg(out)
        .output()
        .unwrap();
    assert_clean_failure(&o, "--aggregate needs --doi");
    let o = subdiv()
        .args([
            "render",
            bunny,
            "--scheme",
            "loop",
            "--doi",
            "silhouette",
            "--skeleton",
            bunny,
            "-o",
        ])
        .arg(out)
        .output()
        .unwrap();
    assert_clean_failure(&o, "--focus and --skeleton need --doi focus");
}

/// `render --doi` takes the DoI options of `subdiv refine` (haptic interaction point,
/// aggregation) and refines exactly as `refine` does; without the DoI they are refused.
#[test]
fn render_doi_options_match_refine() {
    let bunny = root().join("fixtures/meshes/tri_bunny_3k.obj");
    let bunny = bunny.to_str().unwrap();
    let out = tmp("doi_opts.png");
    let obj = tmp("doi_opts.obj");
    // The haptic interaction point at a vertex of the bunny's back.
    let text = std::fs::read_to_string(bunny).unwrap();
    let v = text
        .lines()
        .filter(|l| l.starts_with("v "))
        .nth(1200)
        .unwrap();
    let hip: Vec<&str> = v.split_whitespace().skip(1).collect();
    let hip = format!("--hip={}", hip.join(","));
    let cases: [(&str, Vec<&str>); 2] = [
        ("haptic", vec![hip.as_str()]),
        ("silhouette", vec!["--aggregate", "avg"]),
    ];
    for (doi, extra) in cases {
        let refine = subdiv()
            .args([
                "refine",
                bunny,
                "--doi",
                doi,
                "--eye-relative",
                "0.3,0.4,2.1",
                "-o",
            ])
            .arg(&obj)
            .args(&extra)
            .output()
            .unwrap();
        assert!(refine.status.success(), "refine {doi}: {}", stderr(&refine));
        let rtext = String::from_utf8_lossy(&refine.stdout).to_string();
        let refined = rtext
            .split("-> ")
            .nth(1)
            .and_then(|t| t.split(' ').next())
            .unwrap()
            .to_string();
        let mut args = vec![
            "render",
            bunny,
            "--scheme",
            "loop",
            "--doi",
            doi,
            "--eye-relative",
            "0.3,0.4,2.1",
        ];
        args.extend(&extra);
        args.extend([
            "--shading",
            "doi",
            "--size",
            "120x90",
            "-o",
            out.to_str().unwrap(),
        ]);
        let Some(o) = run_ok(&args) else {
            return;
        };
        let text = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(
            text.contains(&format!("-> {refined} triangles")),
            "{doi}: refine gave {refined} triangles, render: {text}"
        );
    }
    doi_options_without_their_doi_are_refused(bunny, &out);
}

/// `subdiv view --doi` shows the DoI-driven adaptive Loop mesh of `subdiv render --doi`, DoI
/// heat map included, and refines it for the viewer's camera.
#[test]
fn view_doi_screenshot_equals_render() {
    if view_command().is_none() {
        return;
    }
    let teapot = root().join("fixtures/meshes/tri_teapot.obj");
    let flags = [
        teapot.to_str().unwrap(),
        "--split-nonmanifold",
        "--scheme",
        "loop",
        "--doi",
        "silhouette",
        "--eye-relative",
        "0,0.3,2.2",
        "--shading",
        "doi",
        "--size",
        "200x150",
    ];
    let rendered = tmp("view-doi-render.png");
    let Some(r) = run_ok(&[&["render"][..], &flags, &["-o", rendered.to_str().unwrap()]].concat())
    else {
        return;
    };
    let shot = tmp("view-doi-shot.png");
    let o = view_command()
        .unwrap()
        .arg("view")
        .args(flags)
        .args([
            "--screenshot-after",
            "3",
            "--no-hud",
            "-o",
            shot.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = stderr(&o);
    assert!(o.status.success(), "subdiv view --doi failed:\n{err}");
    assert!(
        !err.contains("subdiv-vk validation:"),
        "validation messages:\n{err}"
    );
    // Both report the same refinement.
    let summary = |text: &str| {
        text.split("DoI, threshold")
            .nth(1)
            .and_then(|t| t.split(" triangles").next())
            .map(str::to_string)
    };
    let (rt, vt) = (
        String::from_utf8_lossy(&r.stdout).to_string(),
        String::from_utf8_lossy(&o.stdout).to_string(),
    );
    assert!(
        summary(&vt).is_some() && summary(&rt) == summary(&vt),
        "render: {rt}\nview: {vt}"
    );
    let (a, b) = (read_png(&shot).unwrap(), read_png(&rendered).unwrap());
    assert!(
        a == b,
        "view --doi screenshot differs from subdiv render --doi"
    );
}

/// `subdiv view` on an adaptive Loop cage: a scripted screenshot without the
/// HUD equals `subdiv render` with the same flags.
#[test]
fn view_adaptive_loop_screenshot_equals_render() {
    if view_command().is_none() {
        return;
    }
    let ico = root().join("fixtures/reference/shapes/loop_icosahedron.obj");
    let flags = [
        ico.to_str().unwrap(),
        "--scheme",
        "loop",
        "--eye-relative",
        "0.8,0.6,1.8",
        "--max-depth",
        "4",
        "--shading",
        "depth",
        "--wire-overlay",
        "--size",
        "200x150",
    ];
    let rendered = tmp("view-loop-render.png");
    let Some(r) = run_ok(&[&["render"][..], &flags, &["-o", rendered.to_str().unwrap()]].concat())
    else {
        return;
    };
    assert!(
        String::from_utf8_lossy(&r.stdout).contains("adaptive, max depth 4"),
        "{}",
        String::from_utf8_lossy(&r.stdout)
    );
    let shot = tmp("view-loop-shot.png");
    let o = view_command()
        .unwrap()
        .arg("view")
        .args(flags)
        .args([
            "--screenshot-after",
            "1",
            "--no-hud",
            "-o",
            shot.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = stderr(&o);
    assert!(o.status.success(), "subdiv view failed:\n{err}");
    let (a, b) = (read_png(&shot).unwrap(), read_png(&rendered).unwrap());
    assert!(a == b, "view screenshot differs from subdiv render");
}
