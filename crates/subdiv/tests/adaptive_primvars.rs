//! Vertex and constant primvars on adaptive frames ([`DynamicSubdivision::carry_primvars`]),
//! Catmull-Clark and Loop, measured against the surface itself: a vertex primvar equal to the
//! positions must come out as the frame's points, bit for bit, at every drawn vertex.

use glam::Vec3;

use subdiv::DynamicSubdivision;
use subdiv_depth::DepthParams;
use subdiv_mesh::{Camera, Mesh, UsdReadOptions, read_obj, read_usd};
use subdiv_rules::{LimitMesh, Scheme};
use subdiv_test_support::{colours_from, colours_from_positions, fixture, shape};

/// The cage at `path` with its positions as its colours, read as a file is (non-manifold
/// cages refined as OpenSubdiv refines them).
fn coloured(path: std::path::PathBuf) -> Mesh {
    with_colours(path, colours_from_positions)
}

/// The cage at `path` with the colours `colour(obj text)` writes.
fn with_colours(path: std::path::PathBuf, colour: impl Fn(&str) -> String) -> Mesh {
    let text = colour(&std::fs::read_to_string(&path).unwrap());
    let out = temp_dir().join(path.file_name().unwrap());
    std::fs::write(&out, text).unwrap();
    read_obj(&out).unwrap()
}

fn temp_dir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("subdiv-adaptive-primvars-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The pixel-error mode: depths from 0 to 3 across a frame.
fn params() -> DepthParams {
    DepthParams {
        max_depth: 3,
        pixel_error: Some(2.0),
        ..DepthParams::default()
    }
}

/// The vertices the frame's triangles use.
fn drawn(s: &LimitMesh) -> Vec<usize> {
    let mut v: Vec<usize> = s.face_indices().iter().map(|&i| i as usize).collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// Frames from three cameras (blocks cached and rewritten between them; with `mixed`, depths
/// that differ across each frame): the carried `displayColor` equals the points wherever the
/// frame draws.
fn colours_are_the_points(mesh: Mesh, scheme: Scheme, mixed: bool) {
    let (lo, hi) = mesh.bounds();
    let mut node = DynamicSubdivision::with_scheme(mesh, scheme, params()).unwrap();
    for eye in [
        Vec3::new(0.3, 0.2, 2.5),
        Vec3::new(-1.8, 0.9, 0.6),
        Vec3::new(0.3, 0.2, 1.2),
    ] {
        let camera = Camera::eye_relative(lo, hi, eye, 45.0, 800, 600);
        let depths = node.update(&camera, None).unwrap().unit_depth().to_vec();
        assert!(
            !mixed || depths.iter().min() < depths.iter().max(),
            "{depths:?}"
        );
        assert!(node.carry_primvars().unwrap().is_empty());
        let s = node.geometry().surface();
        let c = s.channel("displayColor").unwrap();
        assert_eq!((c.width, c.values.len()), (3, 3 * s.num_vertices()));
        for v in drawn(s) {
            assert_eq!(c.value(v), s.positions()[v], "vertex {v} from {eye}");
        }
    }
}

#[test]
fn catmull_clark_frames_carry_vertex_primvars_exactly() {
    colours_are_the_points(
        coloured(shape("catmark_pawn.obj")),
        Scheme::CatmullClark,
        true,
    );
    // n-gons (their level-1 patches) and non-manifold cages (seam points from crease chains).
    colours_are_the_points(
        coloured(shape("catmark_nonquads.obj")),
        Scheme::CatmullClark,
        true,
    );
    for cage in ["nonmanifold/fin3_quads.obj", "nonmanifold/cubes_edge.obj"] {
        colours_are_the_points(coloured(fixture(cage)), Scheme::CatmullClark, false);
    }
}

#[test]
fn loop_frames_carry_vertex_primvars_exactly() {
    colours_are_the_points(
        coloured(shape("loop_cubes_semisharp.obj")),
        Scheme::Loop,
        true,
    );
    colours_are_the_points(coloured(shape("loop_icosahedron.obj")), Scheme::Loop, true);
    let fin = fixture("nonmanifold/fin3_tris_loop.obj");
    colours_are_the_points(coloured(fin), Scheme::Loop, false);
}

/// Colours unlike the positions (an affine map of them): the carried values are the map of
/// the frame's points, so every patch (level-1 ones of n-gons, seams of non-manifold edges)
/// reads the primvar, not the positions.
#[test]
fn frames_carry_values_unlike_the_positions() {
    let map = |p: [f64; 3]| {
        [
            2.0 * p[1] + 1.0,
            0.5 * p[2] - p[0],
            p[0] + p[1] + p[2] - 3.0,
        ]
    };
    let mapf = |p: [f32; 3]| map(p.map(f64::from));
    for (cage, scheme) in [
        (shape("catmark_nonquads.obj"), Scheme::CatmullClark),
        (shape("catmark_pawn.obj"), Scheme::CatmullClark),
        (fixture("nonmanifold/cubes_edge.obj"), Scheme::CatmullClark),
        (shape("loop_cubes_semisharp.obj"), Scheme::Loop),
        (fixture("nonmanifold/fin3_tris_loop.obj"), Scheme::Loop),
    ] {
        let mesh = with_colours(cage.clone(), |t| colours_from(t, map));
        let (lo, hi) = mesh.bounds();
        let size = f64::from((hi - lo).length());
        let mut node = DynamicSubdivision::with_scheme(mesh, scheme, params()).unwrap();
        let camera = Camera::eye_relative(lo, hi, Vec3::new(0.3, 0.2, 2.5), 45.0, 800, 600);
        node.update(&camera, None).unwrap();
        assert!(node.carry_primvars().unwrap().is_empty());
        let s = node.geometry().surface();
        let c = s.channel("displayColor").unwrap();
        for v in drawn(s) {
            let want = mapf(s.positions()[v]);
            let got = c.value(v);
            let off = (0..3)
                .map(|k| (f64::from(got[k]) - want[k]).abs())
                .fold(0.0, f64::max);
            assert!(
                off < 1e-5 * size.max(1.0),
                "{cage:?} vertex {v}: {got:?} against {want:?}"
            );
        }
    }
}

/// Every kind of primvar of a stage: vertex ones of any width (four floats: two passes) and
/// constant ones are carried, the varying, uniform and face-varying ones named as left out;
/// the next update writes a frame without channels.
#[test]
fn constant_and_wide_vertex_primvars_and_what_is_left() {
    let text = r#"#usda 1.0
def Mesh "Cube" {
    int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
    int[] faceVertexIndices = [0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1), (1, 1, 1)]
    float4[] primvars:wide = [(0, 0, 0, 0), (1, 0, 0, 1), (0, 1, 0, 1), (1, 1, 0, 2), (0, 0, 1, 0), (1, 0, 1, 1), (0, 1, 1, 1), (1, 1, 1, 2)] (
        interpolation = "vertex"
    )
    float[] primvars:weight = [0.5]
    float[] primvars:opacity = [1, 2, 3, 4, 5, 6] (
        interpolation = "uniform"
    )
    texCoord2f[] primvars:st1 = [(0, 0), (1, 0), (1, 1), (0, 1)] (
        interpolation = "faceVarying"
    )
    int[] primvars:st1:indices = [0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3]
}
"#;
    let path = temp_dir().join("cube.usda");
    std::fs::write(&path, text).unwrap();
    let mesh = read_usd(&path, &UsdReadOptions::default()).unwrap().mesh;
    let (lo, hi) = mesh.bounds();
    let mut node = DynamicSubdivision::new(mesh, params()).unwrap();
    let camera = Camera::eye_relative(lo, hi, Vec3::new(0.3, 0.2, 1.5), 45.0, 800, 600);
    node.update(&camera, None).unwrap();
    assert_eq!(node.carry_primvars().unwrap(), ["opacity", "st1"]);
    let s = node.geometry().surface();
    let (wide, weight) = (s.channel("wide").unwrap(), s.channel("weight").unwrap());
    assert_eq!(wide.width, 4);
    for v in drawn(s) {
        let (w, p) = (wide.value(v), s.positions()[v]);
        // The first three floats are the cube's points; the fourth is x + y, linear in them.
        assert_eq!(&w[..3], &p[..]);
        assert!((w[3] - (p[0] + p[1])).abs() < 1e-5, "vertex {v}: {w:?}");
        assert_eq!(weight.value(v), [0.5]);
    }
    node.update(&camera, None).unwrap();
    assert!(node.geometry().surface().channels().is_empty());
}
