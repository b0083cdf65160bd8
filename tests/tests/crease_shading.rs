//! Smooth shading without dots: every fixture cage and a draw of random creased cages
//! (`cargo xtask fuzz-osd`'s generator), uniform at every depth 0 to 7, rendered smooth as
//! `subdiv render` draws them ([`Scene`], [`view_for`], the renderer), show no dot inside the
//! object at the default sample count: no pixel brighter than all 8 neighbours, or darker than
//! all 8, by more than 40 grey levels. The test prints what it finds at one sample per pixel.
//!
//! Inside the object: the pixel and its 8 neighbours show one continuous piece of surface, read
//! from the render's linear depth (point-sampled at pixel centres whatever the sample count):
//! all nine on the surface, and along each of the four lines through the pixel the depth
//! continues without a jump (second difference at most 3 % of the depth). A lone pixel of a
//! farther surface showing through at an occluding contour is geometry, and is left out; a
//! crease is continuous in depth (a kink) and is judged, thin strips and all.
//!
//! A dot is an extreme, not a difference: with several samples per pixel a pixel on an edge
//! between two regions 80 grey levels apart takes a value between them, more than 40 from every
//! neighbour when none shares its coverage, and is no dot.
//!
//! What made the dots: at one sample per pixel, strips narrower than a pixel beside a crease
//! (whose corners carry the one-sided normals) are hit by some pixel centres and missed by the
//! next, and a crease seen edge-on becomes a dotted line; with several samples, a strip that
//! covers some samples of a pixel but not its centre took a normal extrapolated far outside its
//! corners' until the renderer interpolated at the centroid; and a corner whose limit normal
//! points against its face (OpenSubdiv's normal at a vertex of valence 2 or a non-manifold
//! vertex, a coarse face of a folded cage) turned the interpolated normal over inside the face
//! until the drawn form reversed it there (`LimitMesh::normals_facing_faces`).
//!
//! Without a Vulkan driver the test prints a note and passes unless
//! `SUBDIV_VK_REQUIRE_DRIVER=1`; with `SUBDIV_VK_REQUIRE_VALIDATION=1` it runs validated and
//! fails on any validation message.

use std::path::Path;

use subdiv::mesh::{Camera, Mesh, glam::Vec3, read_obj};
use subdiv::rules::Scheme;
use subdiv::vk::image::{Rgba, RgbaImage};
use subdiv::vk::{ContextOptions, RenderOptions, Renderer, Validation, VkError};
use subdiv::{Scene, framing_box, view_for};
use subdiv_test_support::fixture_files;
use subdiv_tests::osd_gen::random_cage;

/// Image size and camera of every render: small enough for CI (about 1,000 renders), large
/// enough that every cage covers a few thousand pixels.
const SIZE: [u32; 2] = [200, 150];
const EYE_RELATIVE: Vec3 = Vec3::new(0.6, 0.5, 2.2);
/// Depths drawn.
const DEPTHS: std::ops::RangeInclusive<u8> = 0..=7;
/// Random creased cages drawn from `fuzz-osd`'s generator, with its default seed.
const RANDOM_CAGES: usize = 20;
const RANDOM_SEED: u64 = 1;
/// Grey levels a dot differs by from all its neighbours.
const DOT: i32 = 40;
/// Largest depth jump (second difference along a line of three pixels, relative to the
/// centre's depth) of one continuous surface.
const JUMP: f32 = 0.03;

/// The dots of `img` inside the object: pixels brighter than all 8 neighbours, or darker than
/// all 8, by more than [`DOT`] grey levels, where the 3x3 block is one continuous surface in
/// `depth` (row-major linear depth, +inf on the background).
fn dots(img: &RgbaImage, depth: &[f32]) -> Vec<(u32, u32)> {
    let (w, h) = img.dimensions();
    let grey = |x: i32, y: i32| {
        let p = img.get_pixel(x as u32, y as u32).0;
        (i32::from(p[0]) + i32::from(p[1]) + i32::from(p[2])) / 3
    };
    let z = |x: i32, y: i32| depth[(y as u32 * w + x as u32) as usize];
    let continuous = |x: i32, y: i32| {
        let c = z(x, y);
        c.is_finite()
            && [(1, 0), (0, 1), (1, 1), (1, -1)].iter().all(|&(dx, dy)| {
                let (a, b) = (z(x + dx, y + dy), z(x - dx, y - dy));
                a.is_finite() && b.is_finite() && (a + b - 2.0 * c).abs() <= JUMP * c
            })
    };
    let mut out = Vec::new();
    for y in 1..h as i32 - 1 {
        for x in 1..w as i32 - 1 {
            let g = grey(x, y);
            let around = || {
                (-1..=1)
                    .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                    .filter(|&d| d != (0, 0))
                    .map(|(dx, dy)| grey(x + dx, y + dy))
            };
            let bright = around().all(|n| g - n > DOT);
            let dark = around().all(|n| n - g > DOT);
            if (bright || dark) && continuous(x, y) {
                out.push((x as u32, y as u32));
            }
        }
    }
    out
}

#[test]
fn the_counter_finds_a_lone_dark_pixel_and_no_edge() {
    let grey = |v: u8| Rgba([v, v, v, 255]);
    let mut img = RgbaImage::from_pixel(8, 8, grey(200));
    let plane: Vec<f32> = (0..64)
        .map(|k| 5.0 + 0.1 * (k % 8) as f32 + 0.05 * (k / 8) as f32)
        .collect();
    assert!(dots(&img, &plane).is_empty());
    img.put_pixel(3, 4, grey(20));
    assert_eq!(dots(&img, &plane), [(3, 4)]);
    // A crease (a kink in depth) is continuous: judged.
    let kink: Vec<f32> = (0..64)
        .map(|k| 5.0 + 0.02 * ((k % 8) as f32 - 3.0).abs())
        .collect();
    assert_eq!(dots(&img, &kink), [(3, 4)]);
    // A farther surface showing through at that pixel is geometry: left out. So is a pixel
    // next to an occluding contour, or next to the background.
    let mut hole = plane.clone();
    hole[4 * 8 + 3] = 7.0;
    assert!(dots(&img, &hole).is_empty());
    let mut contour = plane.clone();
    contour[5 * 8 + 4] = 9.0;
    assert!(dots(&img, &contour).is_empty());
    let mut edge = plane.clone();
    edge[3 * 8 + 2] = f32::INFINITY;
    assert!(dots(&img, &edge).is_empty());
    // Two dark pixels side by side are an edge, not a dot.
    img.put_pixel(4, 4, grey(20));
    assert!(dots(&img, &plane).is_empty());
    // A thin line with one darker pixel on it is a dotted line: the pixel is a dot.
    let mut line = RgbaImage::from_pixel(8, 8, grey(180));
    for x in 0..8 {
        line.put_pixel(x, 4, grey(110));
    }
    line.put_pixel(3, 4, grey(40));
    assert_eq!(dots(&line, &plane), [(3, 4)]);
    // An anti-aliased pixel between a dark and a light region is no dot, though it differs by
    // more than 40 from every neighbour.
    let mut step = RgbaImage::from_pixel(8, 8, grey(40));
    for y in 0..8 {
        for x in 4..8 {
            step.put_pixel(x, y, grey(200));
        }
    }
    step.put_pixel(4, 4, grey(120));
    assert!(dots(&step, &plane).is_empty());
}

/// A headless renderer, or `None` (after a message) where Vulkan is missing and not required.
fn renderer() -> Option<Renderer> {
    let options = ContextOptions {
        validation: Validation::IfAvailable,
        ..Default::default()
    };
    match Renderer::with_options(&options) {
        Ok(r) => Some(r),
        Err(e @ (VkError::LoaderMissing { .. } | VkError::NoDriver { .. }))
            if std::env::var("SUBDIV_VK_REQUIRE_DRIVER").as_deref() != Ok("1") =>
        {
            eprintln!("skipping: {e}");
            None
        }
        Err(e) => panic!("cannot create renderer: {e}"),
    }
}

/// Every fixture cage (`fixtures/reference/shapes`, `fixtures/scenes`; `loop_*` as Loop
/// surfaces) and the first [`RANDOM_CAGES`] cages with creases of `fuzz-osd`'s generator.
fn cages() -> Vec<(String, Mesh, Scheme)> {
    let mut out = Vec::new();
    let mut files = fixture_files("reference/shapes", "obj");
    files.extend(fixture_files("scenes", "obj"));
    for f in files {
        let name = f.file_stem().unwrap().to_string_lossy().into_owned();
        let scheme = if name.starts_with("loop") {
            Scheme::Loop
        } else {
            Scheme::CatmullClark
        };
        out.push((name, read_obj(Path::new(&f)).unwrap(), scheme));
    }
    let mut index = 0;
    let mut drawn = 0;
    while drawn < RANDOM_CAGES {
        let cage = random_cage(RANDOM_SEED, index);
        index += 1;
        if cage.creases.is_empty() {
            continue;
        }
        let scheme = if cage.loop_scheme {
            Scheme::Loop
        } else {
            Scheme::CatmullClark
        };
        let mesh = cage.mesh().expect("the generator draws valid cages");
        out.push((
            format!("random cage {RANDOM_SEED}/{}", index - 1),
            mesh,
            scheme,
        ));
        drawn += 1;
    }
    out
}

#[test]
fn smooth_shading_shows_no_dots_at_any_depth() {
    let Some(mut renderer) = renderer() else {
        return;
    };
    let log = renderer.validation_log();
    let default = RenderOptions::default();
    let one = RenderOptions {
        samples: Some(1),
        ..default
    };
    let samples = renderer.samples(&default).unwrap();
    let cages = cages();
    let (mut surface, mut renders) = (0usize, 0usize);
    let (mut failures, mut at_one) = (Vec::new(), Vec::new());
    for (name, cage, scheme) in &cages {
        let (lo, hi) = framing_box(cage);
        let camera = Camera::eye_relative(lo, hi, EYE_RELATIVE, 45.0, SIZE[0], SIZE[1]);
        let view = view_for(&camera, lo, hi);
        for depth in DEPTHS {
            // Cages whose every face is a hole have nothing to draw.
            let Ok(scene) = Scene::uniform(cage, *scheme, depth) else {
                continue;
            };
            let mesh = scene.render_mesh();
            let (image, aux) = renderer
                .render_with_aux(&mesh, &view, SIZE, &default)
                .unwrap();
            surface += aux.coverage.iter().filter(|&&c| c > 0.0).count();
            renders += 1;
            let found = dots(&image, &aux.depth);
            if !found.is_empty() {
                let first = &found[..found.len().min(5)];
                failures.push((format!("{name} depth {depth} at {first:?}"), found.len()));
            }
            // The same view at one sample per pixel (same depth: the auxiliary images are
            // point-sampled at any sample count).
            let image = renderer.render(&mesh, &view, SIZE, &one).unwrap();
            let found = dots(&image, &aux.depth);
            if !found.is_empty() {
                at_one.push((format!("{name} depth {depth}"), found.len()));
            }
        }
    }
    let total = |v: &[(String, usize)]| v.iter().map(|(_, n)| n).sum::<usize>();
    let list = |v: &[(String, usize)]| {
        v.iter()
            .map(|(what, n)| format!("{what}: {n}"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    println!(
        "{} cages, {renders} renders, {surface} surface pixels: {} dots at {samples} samples per \
         pixel, {} at 1 sample:\n{}",
        cages.len(),
        total(&failures),
        total(&at_one),
        list(&at_one)
    );
    // Every view shows the surface (a few thousand pixels each).
    assert!(surface > renders * 1000, "{surface} surface pixels");
    assert!(
        failures.is_empty(),
        "dots at {samples} samples per pixel:\n{}",
        list(&failures)
    );
    let messages = log.take();
    assert!(messages.is_empty(), "validation messages:\n{messages:?}");
}
