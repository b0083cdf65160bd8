//! The adaptive frame's output, bit for bit: a hash of each frame's surface (the referenced
//! vertices renumbered in order of first use, so the layout of the vertex buffer does not
//! matter: positions, normals, triangles, one-sided corner normals, face-varying values, vertex
//! depths) and its unit depths, for every fixture cage and both schemes, over an orbit of
//! cameras (which exercises the block cache), random fixed depths (fans between any depths) and
//! the pixel-error mode, and for the paper's helmet40 scene; against `adaptive_hashes.txt`.
//!
//! Speed work on the assemblers and the frame loop must not change a bit of what a frame shows.
//! `ADAPTIVE_HASHES_BLESS=1 cargo test -p subdiv --test adaptive_hashes` rewrites the file (see
//! `subdiv_test_support::check_recorded` for the platform rule).

use std::fmt::Write as _;
use std::path::Path;

use glam::Vec3;
use subdiv::depth::DepthParams;
use subdiv::mesh::{Camera, Mesh, ReadOptions, read_obj_with};
use subdiv::rules::{Depth, LimitMesh, Scheme};
use subdiv::stitch::AdaptiveFrame;
use subdiv::{BuiltinScene, DynamicSubdivision};
use subdiv_test_support::{Fnv, Rng, fixture_files};

/// Hash of a frame: its compacted surface and unit depths.
fn hash(g: &AdaptiveFrame) -> u64 {
    let s: LimitMesh = g.surface().referenced_only();
    let mut h = Fnv::new();
    h.u32(s.num_vertices() as u32);
    h.f32s(s.positions().as_flattened());
    h.f32s(s.normals().as_flattened());
    h.u32s(s.face_indices());
    h.u32(s.corner_normals().len() as u32);
    for (k, n) in s.corner_normals() {
        h.u32(*k);
        h.f32s(n);
    }
    h.f32s(s.uvs().as_flattened());
    h.u32s(s.uv_indices());
    if let Some((_, v)) = s.scalar() {
        h.f32s(v);
    }
    h.bytes(g.unit_depth());
    h.0
}

/// Camera `k` of `n` around the cage's bounding box.
fn orbit(mesh: &Mesh, k: usize, n: usize) -> Camera {
    let (lo, hi) = mesh.bounds();
    let a = std::f32::consts::TAU * k as f32 / n as f32;
    let rel = Vec3::new(1.6 * a.cos(), 0.7, 1.6 * a.sin());
    Camera::eye_relative(lo, hi, rel, 45.0, 320, 240)
}

/// Every fixture cage (OpenSubdiv's shapes and the real meshes) with the schemes it takes.
fn cases() -> Vec<(String, Mesh, Scheme)> {
    let mut paths = fixture_files("reference/shapes", "obj");
    paths.extend(fixture_files("meshes", "obj"));
    let opts = ReadOptions {
        split_nonmanifold_vertices: true,
    };
    let mut out = Vec::new();
    for p in paths {
        let mesh = read_obj_with(&p, opts).unwrap_or_else(|e| panic!("{e}"));
        let name = p.file_stem().unwrap_or_default().to_string_lossy();
        let tris = mesh.faces().all(|f| mesh.face_size(f) == 3);
        out.push((format!("{name} cc"), mesh.clone(), Scheme::CatmullClark));
        if tris {
            out.push((format!("{name} loop"), mesh, Scheme::Loop));
        }
    }
    out
}

/// One line per frame: `case mode frame triangles hash`.
fn lines() -> String {
    let mut out = String::new();
    let mut rng = Rng::xorshift(0x5eed_adab);
    let mut line = |case: &str, mode: &str, i: usize, g: &AdaptiveFrame| {
        writeln!(
            out,
            "{case} {mode} {i} {} {:016x}",
            g.num_triangles(),
            hash(g)
        )
        .expect("write to a string");
    };
    for (case, mesh, scheme) in cases() {
        let max_depth: Depth = if mesh.num_faces() > 1000 { 2 } else { 3 };
        let params = DepthParams {
            max_depth,
            ..DepthParams::default()
        };
        let mut node = DynamicSubdivision::with_scheme(mesh.clone(), scheme, params)
            .unwrap_or_else(|e| panic!("{case}: {e}"));
        for i in 0..4 {
            let g = node.update(&orbit(&mesh, i, 4), None).expect("frame");
            line(&case, "orbit", i, g);
        }
        let nf = mesh.num_faces();
        for i in 0..3 {
            let d: Vec<Depth> = (0..nf)
                .map(|_| rng.below(max_depth as usize + 1) as Depth)
                .collect();
            node.set_face_depths(Some(d)).expect("depths");
            let g = node.update(&orbit(&mesh, i, 3), None).expect("frame");
            line(&case, "fixed", i, g);
        }
        if nf <= 600 {
            node.set_face_depths(None).expect("depths");
            node.set_params(DepthParams {
                pixel_error: Some(1.0),
                ..params
            })
            .expect("params");
            for i in 0..2 {
                let g = node.update(&orbit(&mesh, i, 2), None).expect("frame");
                line(&case, "pixel", i, g);
            }
        }
    }
    let scene = BuiltinScene::Helmet40.cage().expect("helmet40");
    let mut node = DynamicSubdivision::new(
        scene.clone(),
        DepthParams {
            max_depth: 4,
            ..DepthParams::default()
        },
    )
    .expect("helmet40");
    for i in 0..3 {
        let g = node.update(&orbit(&scene, i, 24), None).expect("frame");
        line("helmet40 cc", "orbit", i, g);
    }
    out
}

#[test]
fn adaptive_output_is_bit_identical_to_the_recorded_hashes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/adaptive_hashes.txt");
    subdiv_test_support::check_recorded(&path, &lines(), "ADAPTIVE_HASHES_BLESS");
}
