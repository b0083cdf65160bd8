//! Headless rendering on the installed Vulkan driver (lavapipe on CI).
//!
//! Every test enables the Khronos validation layer when it is installed and
//! fails on any validation message. Without any Vulkan driver the tests print
//! a note and pass, unless `SUBDIV_VK_REQUIRE_DRIVER=1` is set.

mod common;

use common::{SIZE, WHITE, finish, front_view, px, renderer, square, tilted_square};
use subdiv_vk::{OrbitCamera, RenderMesh, RenderOptions, Shading, VkError};

#[test]
fn smooth_square_centre_is_shaded_corners_are_background() {
    let Some(mut r) = renderer() else { return };
    let sq = square(0.0);
    let img = r
        .render(
            &sq.mesh(),
            &front_view(64.0 / 48.0),
            SIZE,
            &RenderOptions::default(),
        )
        .unwrap();
    assert_eq!(img.dimensions(), (64, 48));
    let c = px(&img, 32, 24);
    assert_ne!(c, WHITE, "centre should be shaded");
    assert!(c[0] == c[1] && c[1] == c[2], "grey material, got {c:?}");
    assert!(c[0] > 100 && c[0] < 250, "lit grey, got {c:?}");
    for (x, y) in [(0, 0), (63, 0), (0, 47), (63, 47)] {
        assert_eq!(
            px(&img, x, y),
            WHITE,
            "corner ({x}, {y}) should be background"
        );
    }
    finish(r);
}

/// The square turned by 30 degrees about the view axis: edges that cross the pixel grid.
#[test]
fn multisampling_smooths_edges_and_leaves_aux_images_point_sampled() {
    let Some(mut r) = renderer() else { return };
    let sq = tilted_square();
    let view = front_view(64.0 / 48.0);
    let one = RenderOptions {
        samples: Some(1),
        ..Default::default()
    };
    let default = RenderOptions::default();
    let n = r.samples(&default).unwrap();
    assert!(r.sample_counts().contains(&n) && n <= subdiv_vk::DEFAULT_SAMPLES);
    if r.sample_counts().contains(&subdiv_vk::DEFAULT_SAMPLES) {
        assert_eq!(n, subdiv_vk::DEFAULT_SAMPLES);
    }
    let (img1, aux1) = r.render_with_aux(&sq.mesh(), &view, SIZE, &one).unwrap();
    let (img, aux) = r
        .render_with_aux(&sq.mesh(), &view, SIZE, &default)
        .unwrap();
    // Depth, normals, scalars and coverage do not depend on the sample count.
    assert_eq!(aux, aux1);
    // Pixels away from the silhouette keep their shade; pixels on it blend the surface with
    // the background.
    let covered = |x: i64, y: i64| {
        let (w, h) = (i64::from(SIZE[0]), i64::from(SIZE[1]));
        x >= 0 && y >= 0 && x < w && y < h && aux.coverage[(y * w + x) as usize] > 0.0
    };
    let mut blended = 0;
    for (x, y, p) in img.enumerate_pixels() {
        let (xi, yi) = (i64::from(x), i64::from(y));
        let near_edge =
            (-1..=1).any(|dy| (-1..=1).any(|dx| covered(xi + dx, yi + dy) != covered(xi, yi)));
        if !near_edge {
            assert_eq!(p.0, px(&img1, x, y), "pixel ({x}, {y}) off the silhouette");
        } else if p.0 != px(&img1, x, y) {
            blended += 1;
        }
    }
    assert_eq!(
        n > 1,
        blended > 0,
        "{blended} blended silhouette pixels at {n} samples"
    );
    // The same image again (the multisampled target is kept), and a render without
    // readback draws as well.
    assert_eq!(r.render(&sq.mesh(), &view, SIZE, &default).unwrap(), img);
    r.render_discard(&sq.mesh(), &view, SIZE, &default).unwrap();
    finish(r);
}

#[test]
fn a_sample_count_the_device_lacks_is_an_error() {
    let Some(mut r) = renderer() else { return };
    let have = r.sample_counts();
    assert!(have.contains(&1));
    let sq = square(0.0);
    for n in subdiv_vk::SAMPLE_COUNTS {
        let options = RenderOptions {
            samples: Some(n),
            ..Default::default()
        };
        let drawn = r.render(&sq.mesh(), &front_view(1.0), [16, 16], &options);
        if have.contains(&n) {
            drawn.unwrap();
        } else {
            let e = drawn.unwrap_err();
            assert!(
                matches!(e, VkError::Samples { requested, .. } if requested == n),
                "{e}"
            );
            let message = e.to_string();
            assert!(
                message.contains(&format!("{n} samples per pixel"))
                    && message.contains(r.device_name()),
                "{message}"
            );
        }
    }
    finish(r);
}

#[test]
fn image_is_not_upside_down() {
    let Some(mut r) = renderer() else { return };
    // A triangle in the upper half of the view only.
    let positions = [[-1.0, 0.2, 0.0], [1.0, 0.2, 0.0], [0.0, 1.0, 0.0]];
    let normals = [[0.0, 0.0, 1.0]; 3];
    let mesh = RenderMesh {
        positions: &positions,
        normals: &normals,
        triangles: &[0, 1, 2],
        ..Default::default()
    };
    let img = r
        .render(&mesh, &front_view(1.0), [64, 64], &RenderOptions::default())
        .unwrap();
    assert_ne!(px(&img, 32, 20), WHITE, "upper half covered");
    assert_eq!(px(&img, 32, 44), WHITE, "lower half empty");
    finish(r);
}

#[test]
fn every_shading_mode_renders_cleanly() {
    let Some(mut r) = renderer() else { return };
    let sq = square(2.0);
    let view = front_view(64.0 / 48.0);
    for (shading, name) in Shading::ALL {
        for wire_overlay in [false, true] {
            let options = RenderOptions {
                shading,
                wire_overlay,
                ..Default::default()
            };
            let img = r.render(&sq.mesh(), &view, SIZE, &options).unwrap();
            let centre = px(&img, 32, 24);
            if shading == Shading::Wire {
                assert_eq!(centre, WHITE, "{name}: the wireframe has no interior lines");
            } else {
                assert_ne!(centre, WHITE, "{name}: centre shaded");
            }
        }
    }
    finish(r);
}

#[test]
fn depth_mode_uses_the_palette_and_doi_the_heat_map() {
    let Some(mut r) = renderer() else { return };
    let view = front_view(64.0 / 48.0);
    // Depth 2 is green in the palette.
    let sq = square(2.0);
    let options = RenderOptions {
        shading: Shading::Depth,
        ..Default::default()
    };
    let c = px(
        &r.render(&sq.mesh(), &view, SIZE, &options).unwrap(),
        32,
        24,
    );
    assert!(
        c[1] > c[0] && c[1] > c[2],
        "depth 2 should be green, got {c:?}"
    );
    // Heat map: the top of the range is red, the bottom blue.
    let options = RenderOptions {
        shading: Shading::Doi,
        scalar_range: Some((0.0, 1.0)),
        ..Default::default()
    };
    let hot = px(
        &r.render(&square(1.0).mesh(), &view, SIZE, &options)
            .unwrap(),
        32,
        24,
    );
    assert!(
        hot[0] > hot[1] && hot[0] > hot[2],
        "hot should be red, got {hot:?}"
    );
    let cold = px(
        &r.render(&square(0.0).mesh(), &view, SIZE, &options)
            .unwrap(),
        32,
        24,
    );
    assert!(
        cold[2] > cold[0] && cold[2] > cold[1],
        "cold should be blue, got {cold:?}"
    );
    finish(r);
}

/// Colour shading draws each vertex's colour, lit; without colours it is the smooth grey.
#[test]
fn color_mode_draws_the_vertex_colours() {
    let Some(mut r) = renderer() else { return };
    let view = front_view(64.0 / 48.0);
    let sq = square(0.0);
    let options = RenderOptions {
        shading: Shading::Color,
        ..Default::default()
    };
    // Red on the left edge, blue on the right: the left of the image red, the right blue.
    let colors = [
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
    ];
    let mesh = RenderMesh {
        colors: Some(&colors),
        ..sq.mesh()
    };
    let img = r.render(&mesh, &view, SIZE, &options).unwrap();
    let (left, right) = (px(&img, 20, 24), px(&img, 44, 24));
    assert!(
        left[0] > 100 && left[1] < 40 && left[2] < 100,
        "left should be red, got {left:?}"
    );
    assert!(
        right[2] > 100 && right[1] < 40 && right[0] < 100,
        "right should be blue, got {right:?}"
    );
    let grey = r.render(&sq.mesh(), &view, SIZE, &options).unwrap();
    let smooth = r
        .render(&sq.mesh(), &view, SIZE, &RenderOptions::default())
        .unwrap();
    assert_eq!(px(&grey, 32, 24), px(&smooth, 32, 24));
    finish(r);
}

/// The legend is drawn into the colour image only, in the top-right corner, in the palette's
/// colour; depth, normals and scalars read back are those of the render without it.
#[test]
fn legend_is_in_the_colour_image_only() {
    let Some(mut r) = renderer() else { return };
    let size = [160, 120];
    let view = front_view(160.0 / 120.0);
    let sq = square(2.0);
    let plain = RenderOptions {
        shading: Shading::Depth,
        ..Default::default()
    };
    let legend = RenderOptions {
        legend: true,
        ..plain
    };
    let (a, aux_a) = r.render_with_aux(&sq.mesh(), &view, size, &plain).unwrap();
    let (b, aux_b) = r.render_with_aux(&sq.mesh(), &view, size, &legend).unwrap();
    assert!(aux_a == aux_b, "the legend reached the auxiliary targets");
    let mut swatch = 0;
    for (x, y, p) in b.enumerate_pixels() {
        if p != a.get_pixel(x, y) {
            assert!(x >= 110 && y < 40, "legend pixel at ({x}, {y})");
        }
        // Depth 2's palette colour (0.20, 0.80, 0.25), unlit, as a 7x7 swatch.
        if p.0 == [51, 204, 64, 255] {
            swatch += 1;
        }
    }
    assert_eq!(swatch, 49);
    finish(r);
}

#[test]
fn wire_overlay_and_lines_are_drawn() {
    let Some(mut r) = renderer() else { return };
    let sq = square(0.0);
    let view = front_view(1.0);
    let plain = r
        .render(&sq.mesh(), &view, [64, 64], &RenderOptions::default())
        .unwrap();
    // A horizontal red segment through the centre, in front of nothing in particular.
    let lines = [[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0]];
    let with_lines = RenderMesh {
        lines: Some(&lines),
        ..sq.mesh()
    };
    let img = r
        .render(&with_lines, &view, [64, 64], &RenderOptions::default())
        .unwrap();
    let column: Vec<[u8; 4]> = (28..36).map(|y| px(&img, 32, y)).collect();
    assert!(
        column.iter().any(|c| c[0] > 150 && c[1] < 80 && c[2] < 80),
        "a red line crosses the centre column: {column:?}"
    );
    let hidden = RenderOptions {
        show_lines: false,
        ..Default::default()
    };
    assert_eq!(
        r.render(&with_lines, &view, [64, 64], &hidden).unwrap(),
        plain
    );
    // The overlay darkens the square's outline: one pixel wide at one sample per pixel,
    // anti-aliased (lighter, over more pixels) at the default.
    let overlay = RenderOptions {
        wire_overlay: true,
        samples: Some(1),
        ..Default::default()
    };
    let img = r.render(&sq.mesh(), &view, [64, 64], &overlay).unwrap();
    let dark = img.pixels().filter(|p| p.0[0] < 40).count();
    assert!(dark > 40, "outline pixels drawn: {dark}");
    let overlay = RenderOptions {
        samples: None,
        ..overlay
    };
    let img = r.render(&sq.mesh(), &view, [64, 64], &overlay).unwrap();
    let darker = img.pixels().filter(|p| p.0[0] < 128).count();
    assert!(darker > 40, "outline pixels drawn: {darker}");
    finish(r);
}

#[test]
fn aux_images_and_exr_have_sane_values() {
    let Some(mut r) = renderer() else { return };
    let sq = square(3.0);
    let options = RenderOptions {
        shading: Shading::Depth,
        ..Default::default()
    };
    let (_, aux) = r
        .render_with_aux(&sq.mesh(), &front_view(64.0 / 48.0), SIZE, &options)
        .unwrap();
    let centre = aux.index(32, 24).unwrap();
    assert!(
        (aux.depth[centre] - 4.0).abs() < 1e-3,
        "depth {}",
        aux.depth[centre]
    );
    assert_eq!(aux.coverage[centre], 1.0);
    let n = aux.normals[centre];
    assert!(
        (n[2] - 1.0).abs() < 1e-5 && n[0].abs() < 1e-5 && n[1].abs() < 1e-5,
        "normal {n:?}"
    );
    assert!((aux.scalars[centre] - 3.0).abs() < 1e-5);
    let corner = aux.index(0, 0).unwrap();
    assert!(aux.depth[corner].is_infinite() && aux.coverage[corner] == 0.0);

    let dir = std::env::temp_dir().join(format!("subdiv-vk-test-{}", std::process::id()));
    let path = dir.join("aux.exr");
    subdiv_vk::write_exr(&path, &aux).unwrap();
    let (w, h, channels) = subdiv_vk::read_exr(&path).unwrap();
    assert_eq!((w, h), (64, 48));
    let z = channels.iter().find(|c| c.name == "Z").unwrap();
    assert_eq!(z.samples, aux.depth);
    let s = channels.iter().find(|c| c.name == "S").unwrap();
    assert_eq!(s.samples[centre], 3.0);
    for name in subdiv_vk::EXR_CHANNELS {
        assert!(channels.iter().any(|c| c.name == name), "channel {name}");
    }
    let png = dir.join("colour.png");
    let img = r
        .render(&sq.mesh(), &front_view(64.0 / 48.0), SIZE, &options)
        .unwrap();
    subdiv_vk::write_png(&png, &img).unwrap();
    assert_eq!(subdiv_vk::read_png(&png).unwrap(), img);
    let _ = std::fs::remove_dir_all(&dir);
    finish(r);
}

#[test]
fn rendering_is_deterministic_and_resizes() {
    let Some(mut r) = renderer() else { return };
    let sq = square(1.0);
    let cam = OrbitCamera::framing_mesh(&sq.mesh());
    let options = RenderOptions {
        shading: Shading::Smooth,
        wire_overlay: true,
        ..Default::default()
    };
    let a = r
        .render(&sq.mesh(), &cam.view(1.5), [96, 64], &options)
        .unwrap();
    let b = r
        .render(&sq.mesh(), &cam.view(1.0), [32, 32], &options)
        .unwrap();
    let c = r
        .render(&sq.mesh(), &cam.view(1.5), [96, 64], &options)
        .unwrap();
    assert_eq!(b.dimensions(), (32, 32));
    assert_eq!(a, c);
    // A second renderer (own instance and device) gives the same bytes.
    let Some(mut r2) = renderer() else { return };
    assert_eq!(
        r2.render(&sq.mesh(), &cam.view(1.5), [96, 64], &options)
            .unwrap(),
        a
    );
    finish(r2);
    finish(r);
}

#[test]
fn parallel_renderers_in_threads() {
    if renderer().is_none() {
        return;
    }
    let handles: Vec<_> = (0..4)
        .map(|i| {
            std::thread::spawn(move || {
                let mut r = renderer().expect("driver present");
                let sq = square(i as f32);
                let options = RenderOptions {
                    shading: Shading::Depth,
                    ..Default::default()
                };
                let mut last = None;
                for _ in 0..3 {
                    let img = r
                        .render(&sq.mesh(), &front_view(1.0), [48, 48], &options)
                        .unwrap();
                    if let Some(prev) = &last {
                        assert_eq!(prev, &img);
                    }
                    last = Some(img);
                }
                finish(r);
            })
        })
        .collect();
    for h in handles {
        h.join().expect("render thread panicked");
    }
}
