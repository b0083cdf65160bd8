//! A cage's primvars on its uniform and adaptive tessellations: `subdiv render --shading
//! primvar:NAME`, the modes that carry no primvars refusing it, and the colours an adaptive
//! `subdiv tessellate` writes.
//!
//! Without a Vulkan driver the render tests print a note and pass, unless
//! `SUBDIV_VK_REQUIRE_DRIVER=1` (set by `cargo xtask test`).

mod common;

use common::{assert_fails, root, run, run_ok, tmp};
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
fn primvar_shading_names_what_is_carried() {
    let input = pawn();
    let out = tmp("refused.png");
    let out = out.to_str().unwrap();
    assert_fails(
        &["render", &input, "--shading", "primvar:st1", "-o", out],
        "no primvar 'st1' on the surface (it carries: displayColor)",
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

/// Runs `subdiv COMMAND PAWN --eye-relative 1.5,-1.7,0.9 --up 0,0,1 FLAGS -o OUT.obj` and
/// checks that it warns of no primvar and that every vertex colour of its output is the vertex's
/// position mapped into the pawn's bounding box: the pawn's colours are its positions mapped
/// into the unit cube (`make_pawn_colors.py`, to 4 decimals), an affine map, so the colour of
/// every limit or refined point is that map of the point. Returns the pawn and the output.
fn colours_follow_the_points(
    command: &str,
    flags: &[&str],
) -> (subdiv_mesh::Mesh, subdiv_mesh::Mesh) {
    let out = tmp(&format!("pawn_{command}_{}.obj", flags.join("_")));
    let input = pawn();
    let mut args = vec![
        command,
        &input,
        "--eye-relative",
        "1.5,-1.7,0.9",
        "--up",
        "0,0,1",
    ];
    args.extend(flags);
    args.extend(["-o", out.to_str().unwrap()]);
    let (code, _, err) = run(&args);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("primvars"), "{err}");
    let cage = subdiv_mesh::read_obj(root().join("fixtures/scenes/pawn_colors.obj")).unwrap();
    let (lo, hi) = cage.bounds();
    let surface = subdiv_mesh::read_obj(&out).unwrap();
    let colours = surface.primvar("displayColor").unwrap();
    for (v, p) in surface.positions().iter().enumerate() {
        let want = (*p - lo) / (hi - lo);
        let got = colours.element(v);
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() < 2e-4,
                "vertex {v}: {got:?} against {want}"
            );
        }
    }
    (cage, surface)
}

/// The adaptive tessellation carries the colours.
#[test]
fn adaptive_tessellation_writes_the_vertex_colours() {
    let flags = ["--pixel-error", "1", "--max-depth", "4"];
    let (cage, surface) = colours_follow_the_points("tessellate", &flags);
    assert!(surface.num_vertices() > 10 * cage.num_vertices());
}

/// DoI-driven refinement carries the colours: the refined OBJ cage keeps them as vertex
/// colours, refined as its points are.
#[test]
fn refinement_writes_the_vertex_colours() {
    let flags = ["--triangulate", "--doi", "view-angle", "--steps", "2"];
    let (cage, refined) = colours_follow_the_points("refine", &flags);
    assert!(refined.num_faces() > 4 * cage.num_faces());
}

/// Dicing carries vertex primvars: each point's colour is evaluated at its parameter point.
#[test]
fn dicing_writes_the_vertex_colours() {
    let (cage, surface) = colours_follow_the_points("tessellate", &["--dicing-rate", "4"]);
    assert!(surface.num_vertices() > cage.num_vertices());
}

/// Dicing carries the UVs, seams included: the cube's cross unwrap comes out with more UV values
/// than points (each side of a seam its own), no triangle spanning a seam, and no warning.
#[test]
fn dicing_writes_the_uvs_with_their_seams() {
    let out = tmp("cube_uv_diced.obj");
    let input = root().join("fixtures/usd/cube_uv.usda");
    let args = [
        "tessellate",
        input.to_str().unwrap(),
        "--dicing-rate",
        "8",
        "-o",
        out.to_str().unwrap(),
    ];
    let (code, _, err) = run(&args);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("primvars"), "{err}");
    let surface = subdiv_mesh::read_obj(&out).unwrap();
    let uv = surface.uv().expect("UVs written");
    assert!(
        uv.values.len() > surface.num_vertices(),
        "{}",
        uv.values.len()
    );
    let (offsets, _) = surface.face_lists();
    for f in 0..surface.num_faces() {
        let corners = offsets[f] as usize..offsets[f + 1] as usize;
        let t: Vec<_> = corners.map(|c| uv.corner(c)).collect();
        let longest = (0..t.len())
            .map(|i| t[i].distance(t[(i + 1) % t.len()]))
            .fold(0.0, f32::max);
        assert!(longest < 0.15, "face {f}: {t:?}");
    }
}
