//! Smooth shading without speckles: every fixture cage rendered in smooth shading at
//! depths 0 to 6 has no isolated outlier pixel, one whose grey level differs by more than 40
//! from all 8 neighbours. Such pixels came from face normals of tiny faces swapped in for limit
//! normals; the renderer now gets the tessellator's one-sided normals at creases.
//!
//! What counts is shading, not geometry: a pixel is only judged where it and its 8 neighbours
//! show one continuous piece of surface, read from the render's linear depth (`--exr`): all nine
//! on the surface, and along each of the four lines through the pixel the depth continues
//! without a jump (second difference at most 3% of the depth). A lone pixel of a surface
//! showing through at an occluding contour, a one-pixel sliver or a silhouette tip against the
//! background is a depth jump and is left out; a crease is continuous in depth (a kink, whose
//! second difference stays near the pixel's footprint) and is judged. Nor is a pixel on a strip
//! of faces narrower than a pixel (a tight fillet or a row of faces seen edge-on): where the flat
//! render, which has no interpolated normals, shows at that pixel a line at most one pixel wide
//! (its grey more than 40 from both neighbours along some line through it), smooth shading only
//! samples that sub-pixel geometry at a different point across the strip.
//!
//! Without a Vulkan driver the test prints a note and passes (see `render.rs`).

mod common;

use common::{root, run_ok, tmp};
use subdiv_vk::image::RgbaImage;
use subdiv_vk::{read_exr, read_png};

/// `true` if pixel `(x, y)` of `flat` lies on a feature at most one pixel wide: along some line
/// through it (horizontal, vertical or diagonal) its grey differs by more than 40 from both
/// neighbours.
fn on_thin_feature(flat: &RgbaImage, x: u32, y: u32) -> bool {
    let grey = |x: i32, y: i32| {
        let p = flat.get_pixel(x as u32, y as u32).0;
        (i32::from(p[0]) + i32::from(p[1]) + i32::from(p[2])) / 3
    };
    let (x, y) = (x as i32, y as i32);
    let g = grey(x, y);
    [(1, 0), (0, 1), (1, 1), (1, -1)].iter().any(|&(dx, dy)| {
        (grey(x + dx, y + dy) - g).abs() > 40 && (grey(x - dx, y - dy) - g).abs() > 40
    })
}

/// Largest depth jump (second difference along a line of three pixels, relative to the
/// centre's depth) of one continuous surface.
const JUMP: f32 = 0.03;

/// Pixels whose grey level differs by more than 40 from each of their 8 neighbours, where the
/// 3x3 block is one continuous surface in `depth` (row-major linear depth, +inf on the
/// background; `None`: judge every pixel whose block is all surface).
fn isolated_outliers(img: &RgbaImage, depth: Option<&[f32]>) -> Vec<(u32, u32)> {
    let (w, h) = img.dimensions();
    let grey = |x: u32, y: u32| {
        let p = img.get_pixel(x, y).0;
        if p[..3] == [255, 255, 255] {
            return None;
        }
        Some((u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2])) as i32 / 3)
    };
    let continuous = |x: u32, y: u32| {
        let Some(z) = depth else { return true };
        let at =
            |dx: i32, dy: i32| z[((y as i32 + dy) as u32 * w + (x as i32 + dx) as u32) as usize];
        let c = at(0, 0);
        c.is_finite()
            && [(1, 0), (0, 1), (1, 1), (1, -1)].iter().all(|&(dx, dy)| {
                let (a, b) = (at(dx, dy), at(-dx, -dy));
                a.is_finite() && b.is_finite() && (a + b - 2.0 * c).abs() <= JUMP * c
            })
    };
    let mut out = Vec::new();
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let Some(g) = grey(x, y) else { continue };
            let isolated = (-1..=1i32)
                .flat_map(|dy| (-1..=1i32).map(move |dx| (dx, dy)))
                .filter(|&d| d != (0, 0))
                .all(|(dx, dy)| {
                    grey((x as i32 + dx) as u32, (y as i32 + dy) as u32)
                        .is_some_and(|n| (n - g).abs() > 40)
                });
            if isolated && continuous(x, y) {
                out.push((x, y));
            }
        }
    }
    out
}

#[test]
fn the_counter_finds_a_lone_dark_pixel_and_nothing_else() {
    let mut img = RgbaImage::from_pixel(8, 8, subdiv_vk::image::Rgba([200, 200, 200, 255]));
    assert!(isolated_outliers(&img, None).is_empty());
    img.put_pixel(3, 4, subdiv_vk::image::Rgba([20, 20, 20, 255]));
    assert_eq!(isolated_outliers(&img, None), [(3, 4)]);
    // On a tilted plane (depth linear in x and y) it is still judged.
    let plane: Vec<f32> = (0..64)
        .map(|k| 5.0 + 0.1 * (k % 8) as f32 + 0.05 * (k / 8) as f32)
        .collect();
    assert_eq!(isolated_outliers(&img, Some(&plane)), [(3, 4)]);
    // A crease (a kink in depth) is continuous: judged.
    let kink: Vec<f32> = (0..64)
        .map(|k| 5.0 + 0.02 * ((k % 8) as f32 - 3.0).abs())
        .collect();
    assert_eq!(isolated_outliers(&img, Some(&kink)), [(3, 4)]);
    // A farther surface showing through at that pixel is geometry: left out.
    let mut hole = plane.clone();
    hole[4 * 8 + 3] = 7.0;
    assert!(isolated_outliers(&img, Some(&hole)).is_empty());
    // So is a pixel next to an occluding contour, or next to the background.
    let mut contour = plane.clone();
    contour[5 * 8 + 4] = 9.0;
    assert!(isolated_outliers(&img, Some(&contour)).is_empty());
    let mut edge = plane.clone();
    edge[3 * 8 + 2] = f32::INFINITY;
    assert!(isolated_outliers(&img, Some(&edge)).is_empty());
    // The flat render shows a one-pixel line there (a sub-pixel strip): geometry. A crease,
    // two regions meeting, is not thin.
    let mut line = RgbaImage::from_pixel(8, 8, subdiv_vk::image::Rgba([180, 180, 180, 255]));
    for y in 0..8 {
        line.put_pixel(3, y, subdiv_vk::image::Rgba([40, 40, 40, 255]));
    }
    assert!(on_thin_feature(&line, 3, 4));
    let mut crease = RgbaImage::from_pixel(8, 8, subdiv_vk::image::Rgba([180, 180, 180, 255]));
    for y in 0..8 {
        for x in 4..8 {
            crease.put_pixel(x, y, subdiv_vk::image::Rgba([40, 40, 40, 255]));
        }
    }
    assert!(!on_thin_feature(&crease, 3, 4) && !on_thin_feature(&crease, 4, 4));
    // Two dark pixels side by side are an edge, not a speckle.
    img.put_pixel(4, 4, subdiv_vk::image::Rgba([20, 20, 20, 255]));
    assert!(isolated_outliers(&img, None).is_empty());
    // A lone surface pixel on the white background is not counted.
    let mut tip = RgbaImage::from_pixel(8, 8, subdiv_vk::image::Rgba([255, 255, 255, 255]));
    tip.put_pixel(3, 4, subdiv_vk::image::Rgba([90, 90, 90, 255]));
    assert!(isolated_outliers(&tip, None).is_empty());
}

#[test]
fn smooth_shading_has_no_isolated_outlier_pixels() {
    let dir = root().join("fixtures/reference/shapes");
    let mut cages: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "obj"))
        .collect();
    cages.sort();
    assert!(cages.len() >= 30, "{} cages", cages.len());
    let (out, exr) = (tmp("speckle.png"), tmp("speckle.exr"));
    let mut failures = Vec::new();
    let (mut surface, mut jumps, mut thin) = (0usize, 0usize, 0usize);
    for cage in &cages {
        let name = cage.file_stem().unwrap().to_string_lossy().into_owned();
        let scheme = if name.starts_with("loop") {
            "loop"
        } else {
            "catmull-clark"
        };
        for depth in 0..=6 {
            let d = depth.to_string();
            let render = |shading: &str, extra: &[&str]| {
                let args = [
                    "render",
                    cage.to_str().unwrap(),
                    "--scheme",
                    scheme,
                    "--depth",
                    &d,
                    "--eye-relative",
                    "0.6,0.5,2.2",
                    "--size",
                    "200x150",
                    "--shading",
                    shading,
                    "-o",
                    out.to_str().unwrap(),
                ];
                run_ok(&[&args[..], extra].concat()).map(|_| read_png(&out).unwrap())
            };
            let Some(img) = render("smooth", &["--exr", exr.to_str().unwrap()]) else {
                return; // no driver: noted by `run_ok`
            };
            let (_, _, channels) = read_exr(&exr).unwrap();
            let z = &channels
                .iter()
                .find(|c| c.name == "Z")
                .expect("depth")
                .samples;
            surface += z.iter().filter(|z| z.is_finite()).count();
            let mut bad = isolated_outliers(&img, Some(z));
            jumps += isolated_outliers(&img, None).len() - bad.len();
            if !bad.is_empty() {
                let flat = render("flat", &[]).unwrap();
                let before = bad.len();
                bad.retain(|&(x, y)| !on_thin_feature(&flat, x, y));
                thin += before - bad.len();
            }
            if !bad.is_empty() {
                let first = &bad[..bad.len().min(5)];
                failures.push(format!("{name} depth {depth}: {} at {first:?}", bad.len()));
            }
        }
    }
    println!(
        "{surface} surface pixels; lone pixels left out: {jumps} at depth jumps, {thin} on sub-pixel strips"
    );
    // Every view shows the surface (a few thousand pixels each).
    assert!(surface > cages.len() * 7 * 1000, "{surface} surface pixels");
    assert!(
        failures.is_empty(),
        "isolated outlier pixels:\n{}",
        failures.join("\n")
    );
}
