//! The viewer's HUD, legend, pan and up-axis orbit in screenshots under X11 (`DISPLAY` or
//! `xvfb-run`), and the legend of `subdiv render --legend`. Without an X server or a Vulkan
//! driver the tests print a note and pass, unless `SUBDIV_VK_REQUIRE_DISPLAY=1` /
//! `SUBDIV_VK_REQUIRE_DRIVER=1` (set by `cargo xtask test`).

mod common;

use std::path::{Path, PathBuf};

use common::{root, run_ok, stderr, tmp, view_command};
use subdiv_vk::image::RgbaImage;
use subdiv_vk::read_png;

fn pawn() -> PathBuf {
    root().join("fixtures/reference/shapes/catmark_pawn.obj")
}

/// The pawn seen Z-up (the demo's camera) at depth 2, 320x240.
const PAWN_VIEW: [&str; 8] = [
    "--eye-relative",
    "1.5,-1.7,0.9",
    "--up",
    "0,0,1",
    "--depth",
    "2",
    "--size",
    "320x240",
];

/// `subdiv view PAWN FLAGS --screenshot-after 3`: the screenshot, or `None` when skipped.
fn view_shot(name: &str, flags: &[&str]) -> Option<RgbaImage> {
    let mut c = view_command()?;
    let shot = tmp(name);
    let o = c
        .arg("view")
        .arg(pawn())
        .args(PAWN_VIEW)
        .args(flags)
        .args(["--screenshot-after", "3", "-o", shot.to_str().unwrap()])
        .output()
        .unwrap();
    let err = stderr(&o);
    let no_driver =
        err.contains("no Vulkan driver found") || err.contains("cannot load the Vulkan loader");
    if no_driver && std::env::var("SUBDIV_VK_REQUIRE_DRIVER").as_deref() != Ok("1") {
        eprintln!("skipping: {err}");
        return None;
    }
    assert!(o.status.success(), "subdiv view {flags:?} failed:\n{err}");
    assert!(!err.contains("subdiv-vk validation:"), "validation:\n{err}");
    Some(read_png(&shot).unwrap())
}

fn is_background(p: [u8; 4]) -> bool {
    p[0] > 250 && p[1] > 250 && p[2] > 250
}

/// Centroid of the non-background pixels.
fn centroid(img: &RgbaImage) -> (f64, f64) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for (x, y, p) in img.enumerate_pixels() {
        if !is_background(p.0) {
            sx += f64::from(x);
            sy += f64::from(y);
            n += 1.0;
        }
    }
    assert!(n > 100.0, "nothing drawn");
    (sx / n, sy / n)
}

/// Bounding box (x0, y0, x1, y1) of the pixels where `a` and `b` differ, if any.
fn changed_box(a: &RgbaImage, b: &RgbaImage) -> Option<(u32, u32, u32, u32)> {
    let mut bb: Option<(u32, u32, u32, u32)> = None;
    for (x, y, p) in a.enumerate_pixels() {
        if p != b.get_pixel(x, y) {
            bb = Some(match bb {
                None => (x, y, x, y),
                Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
            });
        }
    }
    bb
}

/// The HUD is drawn in the top-left corner (dark panel with white text), the depth legend in
/// the top-right one; everything else equals the screenshot without them.
#[test]
fn hud_and_legend_are_drawn_in_their_corners() {
    let Some(plain) = view_shot("hud-off.png", &["--shading", "depth", "--no-hud"]) else {
        return;
    };
    let Some(hud) = view_shot("hud-on.png", &["--shading", "depth"]) else {
        return;
    };
    let (w, h) = hud.dimensions();
    assert_eq!((w, h), (320, 240));
    // HUD: 6 lines at scale 1 in a panel from (4, 4); legend: "depth" and one level.
    let in_hud = |x: u32, y: u32| x < 200 && y < 72;
    let in_legend = |x: u32, y: u32| x >= w - 60 && y < 40;
    let (mut dark, mut swatch) = (0, 0);
    let mut panel: Option<(u32, u32, u32, u32)> = None;
    for (x, y, p) in hud.enumerate_pixels() {
        let q = plain.get_pixel(x, y);
        if p == q {
            continue;
        }
        assert!(
            in_hud(x, y) || in_legend(x, y),
            "pixel ({x}, {y}) changed outside the corners"
        );
        let [r, g, b, _] = p.0;
        if in_hud(x, y) {
            panel = Some(panel.map_or((x, y, x, y), |(x0, y0, x1, y1)| {
                (x0.min(x), y0.min(y), x1.max(x), y1.max(y))
            }));
        }
        if in_hud(x, y) && r < 100 && g < 100 && b < 100 {
            dark += 1;
        }
        // Depth 2's palette colour (0.20, 0.80, 0.25) as a legend swatch.
        if in_legend(x, y) && r == 51 && g == 204 && b == 64 {
            swatch += 1;
        }
    }
    assert!(dark > 2000, "no HUD panel: {dark} dark pixels");
    // White text inside the (darkened) panel.
    let (x0, y0, x1, y1) = panel.expect("a HUD panel");
    let white = (y0..=y1)
        .flat_map(|y| (x0..=x1).map(move |x| (x, y)))
        .filter(|&(x, y)| hud.get_pixel(x, y).0[..3] == [255, 255, 255])
        .count();
    assert!(white > 300, "no HUD text: {white} white pixels");
    assert_eq!(swatch, 49, "the legend's 7x7 swatch of depth 2");
    // The panel's top-left corner is on the background: dark after blending, not white.
    assert!(is_background(plain.get_pixel(6, 6).0));
    assert!(!is_background(hud.get_pixel(6, 6).0));
}

/// A pan of (+40, +24) pixels moves the picture right and down by about that much; the
/// starting view orbits about --up (the Z-up pawn stands upright, as in `subdiv render`).
#[test]
fn pan_moves_the_picture_with_the_cursor() {
    let Some(start) = view_shot("pan-0.png", &["--no-hud"]) else {
        return;
    };
    let Some(panned) = view_shot("pan-1.png", &["--no-hud", "--pan", "40,24"]) else {
        return;
    };
    let (x0, y0) = centroid(&start);
    let (x1, y1) = centroid(&panned);
    let (dx, dy) = (x1 - x0, y1 - y0);
    // Points in the target plane move exactly with the cursor; nearer and farther ones a
    // little more and less.
    assert!(
        (dx - 40.0).abs() < 8.0 && (dy - 24.0).abs() < 6.0,
        "centroid moved by ({dx:.1}, {dy:.1})"
    );

    // The first frame about +Z matches `subdiv render` of the same camera (it uses the
    // camera's own matrix: equal up to rounding).
    let rendered = tmp("pan-render.png");
    let out = rendered.to_str().unwrap();
    let Some(_) = run_ok(
        &[
            &["render", pawn().to_str().unwrap()][..],
            &PAWN_VIEW,
            &["-o", out],
        ]
        .concat(),
    ) else {
        return;
    };
    let render = read_png(&rendered).unwrap();
    let differing = render
        .pixels()
        .zip(start.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(p, q)| p.abs_diff(q) > 8))
        .count();
    assert!(
        differing < 100,
        "{differing} pixels differ from subdiv render"
    );
    // The pawn stands upright: its picture is much taller than wide.
    let white = RgbaImage::from_pixel(320, 240, subdiv_vk::image::Rgba([255; 4]));
    let (x0, y0, x1, y1) = changed_box(&white, &start).expect("something drawn");
    assert!(
        y1 - y0 > 150 && (y1 - y0) > 3 * (x1 - x0) / 2,
        "pawn box ({x0}, {y0})-({x1}, {y1})"
    );
}

/// `subdiv render --legend` draws the DoI heat map legend top right; without the flag the
/// image has none.
#[test]
fn render_legend_is_optional() {
    let bunny = root().join("fixtures/meshes/tri_bunny_3k.obj");
    let args = |out: &Path, legend: bool| {
        let mut v: Vec<String> = ["render", bunny.to_str().unwrap(), "--doi", "dihedral"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        v.extend(["--shading", "doi", "--size", "320x240", "-o"].map(String::from));
        v.push(out.to_str().unwrap().to_string());
        if legend {
            v.push("--legend".into());
        }
        v
    };
    let (plain, with) = (tmp("legend-off.png"), tmp("legend-on.png"));
    for (path, legend) in [(&plain, false), (&with, true)] {
        let a = args(path, legend);
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        if run_ok(&refs).is_none() {
            return;
        }
    }
    let (a, b) = (read_png(&plain).unwrap(), read_png(&with).unwrap());
    let (x0, y0, x1, y1) = changed_box(&a, &b).expect("the legend changes the image");
    assert!(
        x0 >= 200 && y1 < 120,
        "legend box ({x0}, {y0})-({x1}, {y1})"
    );
    // The heat bar's top is red (high), its bottom blue (low).
    let column: Vec<[u8; 4]> = (y0..=y1).map(|y| b.get_pixel(x0 + 4, y).0).collect();
    let reddest = column.iter().position(|p| p[0] > 100 && p[2] < 30).unwrap();
    let bluest = column
        .iter()
        .rposition(|p| p[2] > 100 && p[0] < 30)
        .unwrap();
    assert!(reddest < bluest, "red at {reddest}, blue at {bluest}");
}
