//! Primvars on adaptive frames ([`DynamicSubdivision::carry_primvars`]), Catmull-Clark and
//! Loop, measured against the surface itself: a vertex primvar equal to the positions must come
//! out as the frame's points, and a face-varying one equal to the texture coordinates as the
//! frame's UVs, bit for bit; affine maps of them as those maps.

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
    // One file per call: the tests run in parallel and may colour one cage differently.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let text = colour(&std::fs::read_to_string(&path).unwrap());
    let name = path.file_name().unwrap().to_string_lossy();
    let out = temp_dir().join(format!("{call}-{name}"));
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
        node.carry_primvars().unwrap();
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
fn bilinear_frames_carry_vertex_primvars_exactly() {
    // The helmet's twisted quads get deeper than its flat ones; the pawn's and the n-gons'
    // nearly flat patches need no depth at 2 px, so their blocks are depth 0 and level 1.
    colours_are_the_points(
        coloured(shape("catmark_helmet.obj")),
        Scheme::Bilinear,
        true,
    );
    for cage in ["catmark_pawn.obj", "catmark_nonquads.obj"] {
        colours_are_the_points(coloured(shape(cage)), Scheme::Bilinear, false);
    }
    let cubes = fixture("nonmanifold/cubes_edge.obj");
    colours_are_the_points(coloured(cubes), Scheme::Bilinear, false);
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
        (shape("catmark_nonquads.obj"), Scheme::Bilinear),
        (shape("loop_cubes_semisharp.obj"), Scheme::Loop),
        (fixture("nonmanifold/fin3_tris_loop.obj"), Scheme::Loop),
    ] {
        let mesh = with_colours(cage.clone(), |t| colours_from(t, map));
        let (lo, hi) = mesh.bounds();
        let size = f64::from((hi - lo).length());
        let mut node = DynamicSubdivision::with_scheme(mesh, scheme, params()).unwrap();
        let camera = Camera::eye_relative(lo, hi, Vec3::new(0.3, 0.2, 2.5), 45.0, 800, 600);
        node.update(&camera, None).unwrap();
        node.carry_primvars().unwrap();
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

/// A stage with UVs (`st`) and every other kind of primvar: `st1` equal to `st`, `st2` an
/// affine map of it, a uniform, a varying (equal everywhere), a wide vertex and a constant one.
fn stage(scheme: &str) -> Mesh {
    let (counts, indices, points, uv_idx) = if scheme == "loop" {
        (
            "3, 3, 3, 3, 3, 3, 3, 3",
            "0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5",
            "(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)",
            "0, 1, 2, 1, 3, 2, 3, 4, 2, 4, 0, 2, 1, 0, 5, 3, 1, 5, 4, 3, 5, 0, 4, 5",
        )
    } else {
        (
            "4, 4, 4, 4, 4, 4",
            "0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5",
            "(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1), (1, 1, 1)",
            "0, 1, 2, 3, 1, 4, 5, 2, 4, 6, 7, 5, 6, 0, 3, 7, 3, 2, 5, 7, 0, 6, 4, 1",
        )
    };
    let n_points = points.matches('(').count();
    let n_faces = counts.split(',').count();
    let uvs =
        "(0, 0), (0.25, 0), (0.25, 0.5), (0, 0.5), (0.5, 0), (0.5, 0.5), (0.75, 0), (0.75, 0.5)";
    let mapped =
        "(1, -3), (1.5, -3), (1.5, -2.5), (1, -2.5), (2, -3), (2, -2.5), (2.5, -3), (2.5, -2.5)";
    let opacity: Vec<String> = (0..n_faces).map(|f| format!("{}", f + 1)).collect();
    let varying = vec!["7"; n_points].join(", ");
    let wide: Vec<String> = points
        .split("), (")
        .map(|p| {
            let c: Vec<f32> = p
                .trim_matches(['(', ')'])
                .split(',')
                .map(|x| x.trim().parse().unwrap())
                .collect();
            format!("({}, {}, {}, {})", c[0], c[1], c[2], c[0] + c[1])
        })
        .collect();
    let text = format!(
        r#"#usda 1.0
def Mesh "M" {{
    uniform token subdivisionScheme = "{scheme}"
    int[] faceVertexCounts = [{counts}]
    int[] faceVertexIndices = [{indices}]
    point3f[] points = [{points}]
    texCoord2f[] primvars:st = [{uvs}] (
        interpolation = "faceVarying"
    )
    int[] primvars:st:indices = [{uv_idx}]
    texCoord2f[] primvars:st1 = [{uvs}] (
        interpolation = "faceVarying"
    )
    int[] primvars:st1:indices = [{uv_idx}]
    texCoord2f[] primvars:st2 = [{mapped}] (
        interpolation = "faceVarying"
    )
    int[] primvars:st2:indices = [{uv_idx}]
    float4[] primvars:wide = [{wide}] (
        interpolation = "vertex"
    )
    float[] primvars:weight = [0.5]
    float[] primvars:opacity = [{opacity}] (
        interpolation = "uniform"
    )
    float[] primvars:level = [{varying}] (
        interpolation = "varying"
    )
}}
"#,
        wide = wide.join(", "),
        opacity = opacity.join(", "),
    );
    let path = temp_dir().join(format!("every_kind_{scheme}.usda"));
    std::fs::write(&path, text).unwrap();
    read_usd(&path, &UsdReadOptions::default()).unwrap().mesh
}

/// Every kind of primvar on frames from two cameras (the second deeper, so the face-varying
/// values are refined further), Catmull-Clark and Loop; the next update writes a frame
/// without channels.
#[test]
fn every_kind_of_primvar_is_carried() {
    for (name, scheme) in [
        ("catmullClark", Scheme::CatmullClark),
        ("loop", Scheme::Loop),
    ] {
        let mesh = stage(name);
        assert_eq!(mesh.primvars().len(), 6, "{name}");
        let faces = mesh.num_faces();
        let (lo, hi) = mesh.bounds();
        let mut node = DynamicSubdivision::with_scheme(mesh, scheme, params()).unwrap();
        for eye in [Vec3::new(0.3, 0.2, 2.5), Vec3::new(0.3, 0.2, 1.1)] {
            let camera = Camera::eye_relative(lo, hi, eye, 45.0, 800, 600);
            node.update(&camera, None).unwrap();
            node.carry_primvars().unwrap();
            let s = node.geometry().surface();
            let channel = |n: &str| s.channel(n).unwrap_or_else(|| panic!("{name}: no {n}"));
            // st1 is st: its value at every corner is the frame's own texture coordinate.
            let (st1, st2) = (channel("st1"), channel("st2"));
            assert!(
                !s.uv_indices().is_empty(),
                "{name}: the frame has texture coordinates"
            );
            assert_eq!(st1.indices.len(), s.face_indices().len());
            assert_eq!(s.uv_indices().len(), s.face_indices().len());
            for (c, &t) in s.uv_indices().iter().enumerate() {
                let uv = s.uvs()[t as usize];
                assert_eq!(st1.value(st1.indices[c] as usize), uv, "{name} corner {c}");
                let m = st2.value(st2.indices[c] as usize);
                let want = [2.0 * uv[0] + 1.0, uv[1] - 3.0];
                assert!(
                    (m[0] - want[0]).abs() < 1e-5 && (m[1] - want[1]).abs() < 1e-5,
                    "{m:?} {want:?}"
                );
            }
            // Uniform: each face's value, every drawn face's; varying: the one value.
            let opacity = channel("opacity");
            let mut seen: Vec<u32> = opacity.values.iter().map(|v| *v as u32).collect();
            seen.sort_unstable();
            seen.dedup();
            assert!(opacity.values.iter().all(|v| v.fract() == 0.0 && *v >= 1.0));
            assert!(seen.len() > 1 && seen.len() <= faces, "{name}: {seen:?}");
            assert!(channel("level").values.iter().all(|&v| v == 7.0));
            let (wide, weight) = (channel("wide"), channel("weight"));
            for v in drawn(s) {
                let (w, p) = (wide.value(v), s.positions()[v]);
                // The first three floats are the points; the fourth is x + y, linear in them.
                assert_eq!(&w[..3], &p[..]);
                assert!((w[3] - (p[0] + p[1])).abs() < 1e-5, "vertex {v}: {w:?}");
                assert_eq!(weight.value(v), [0.5]);
            }
        }
        node.update(
            &Camera::eye_relative(lo, hi, Vec3::Z * 3.0, 45.0, 800, 600),
            None,
        )
        .unwrap();
        assert!(node.geometry().surface().channels().is_empty());
    }
}
