//! `subdiv render --shading primvar:NAME`: a cage's primvar drawn on its uniform tessellation,
//! and the modes that carry no primvars refusing it.
//!
//! Without a Vulkan driver the render tests print a note and pass, unless
//! `SUBDIV_VK_REQUIRE_DRIVER=1` (set by `cargo xtask test`).

mod common;

use common::{assert_fails, root, run_ok, tmp};
use subdiv_vk::read_png;

fn pawn() -> String {
    root()
        .join("fixtures/scenes/pawn_colors.obj")
        .display()
        .to_string()
}

/// The pawn's colours run from its position in the bounding box: the image holds reds, greens
/// and blues where the smooth render is grey, and the summary names the shading.
#[test]
fn vertex_colours_reach_the_image() {
    let (colour, grey) = (tmp("pawn_colors.png"), tmp("pawn_grey.png"));
    let input = pawn();
    let args = |out: &str, shading: &'static str| {
        let v = [
            "render",
            &input,
            "--depth",
            "2",
            "--size",
            "160x120",
            "--shading",
            shading,
            "-o",
            out,
        ];
        v.map(str::to_string)
    };
    let colour_args = args(colour.to_str().unwrap(), "primvar:displayColor");
    let colour_args: Vec<&str> = colour_args.iter().map(String::as_str).collect();
    let Some(o) = run_ok(&colour_args) else {
        return;
    };
    let line = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(line.contains("primvar:displayColor shading"), "{line}");
    let grey_args = args(grey.to_str().unwrap(), "smooth");
    let grey_args: Vec<&str> = grey_args.iter().map(String::as_str).collect();
    run_ok(&grey_args).unwrap();
    let (c, g) = (read_png(&colour).unwrap(), read_png(&grey).unwrap());
    let saturated = |img: &subdiv_vk::image::RgbaImage| {
        img.pixels()
            .filter(|p| {
                let [r, g, b, _] = p.0.map(i32::from);
                r.max(g).max(b) - r.min(g).min(b) > 60
            })
            .count()
    };
    assert_eq!(saturated(&g), 0, "the smooth render is grey");
    assert!(saturated(&c) > 500, "{} coloured pixels", saturated(&c));
    // The same surface: the background pixels are the same.
    let background = |img: &subdiv_vk::image::RgbaImage| {
        img.pixels().map(|p| p.0 == [255; 4]).collect::<Vec<_>>()
    };
    assert_eq!(background(&c), background(&g));
}

#[test]
fn primvar_shading_is_refused_where_no_primvar_is_carried() {
    let input = pawn();
    let out = tmp("refused.png");
    let out = out.to_str().unwrap();
    assert_fails(
        &["render", &input, "--shading", "primvar:st1", "-o", out],
        "no primvar 'st1' on the surface (it carries: displayColor)",
    );
    assert_fails(
        &[
            "render",
            &input,
            "--pixel-error",
            "1",
            "--shading",
            "primvar:displayColor",
            "-o",
            out,
        ],
        "primvars are carried by the uniform tessellation (--depth N) only",
    );
    assert_fails(
        &["render", &input, "--shading", "shiny", "-o", out],
        "give smooth, flat, wire, depth, doi or primvar:NAME",
    );
    assert_fails(
        &["view", &input, "--shading", "primvar:displayColor"],
        "the viewer shows no primvars",
    );
}
