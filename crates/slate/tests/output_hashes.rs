//! The slate tessellator's output, bit for bit: a hash of the positions, normals, quads and
//! one-sided corner normals of every fixture cage at depths 0..=6, on 1 and 2 threads, against
//! the hashes recorded in `output_hashes.txt`.
//!
//! Speed work on the slates must not change a single bit of the output. The
//! recorded hashes were computed by the code before that work (commit c0aba42, x86_64 Linux,
//! glibc). Bits depend on IEEE `f32`/`f64` arithmetic (Rust never contracts to FMA; glam's SIMD
//! and scalar paths sum in the same order, which this test cannot check elsewhere) and on the
//! platform's `sin`/`cos`, which the limit masks of extraordinary vertices use; the file records
//! a fingerprint of those, and on a platform whose fingerprint differs the test compares the
//! thread counts and a repeated run with each other only, and says so.
//!
//! Each case is also run with the SIMD paths off (`set_simd(false)`, depths 2 and up), so a CPU
//! with AVX2 checks the scalar paths too.
//!
//! `SLATE_HASHES_BLESS=1 cargo test -p subdiv-slate --test output_hashes` rewrites the file.

use std::fmt::Write as _;
use std::path::Path;

use subdiv_rules::LimitMesh;
use subdiv_slate::{PatchLayout, tessellate, tessellate_layout_into};
use subdiv_test_support::{Fnv, fixtures};

/// Deepest depth checked.
const MAX_DEPTH: subdiv_rules::Depth = 6;

fn hash(t: &LimitMesh) -> u64 {
    let mut h = Fnv::new();
    h.u32(t.positions().len() as u32);
    h.f32s(t.positions().as_flattened());
    h.f32s(t.normals().as_flattened());
    h.u32(t.face_offsets().len() as u32);
    for &x in t.face_offsets().iter().chain(t.face_indices()) {
        h.u32(x);
    }
    h.u32(t.corner_normals().len() as u32);
    for (k, n) in t.corner_normals() {
        h.u32(*k);
        h.f32s(n);
    }
    h.0
}

/// Every fixture cage (OpenSubdiv's shapes of both schemes and the real meshes), by file stem.
fn cages() -> Vec<(String, subdiv_mesh::Mesh)> {
    let mut paths = Vec::new();
    for dir in ["reference/shapes", "meshes"] {
        for e in std::fs::read_dir(fixtures().join(dir)).expect("fixtures directory") {
            let p = e.expect("directory entry").path();
            if p.extension().is_some_and(|x| x == "obj") {
                paths.push(p);
            }
        }
    }
    paths.sort();
    let opts = subdiv_mesh::ReadOptions {
        split_nonmanifold_vertices: true,
    };
    paths
        .into_iter()
        .map(|p| {
            let m = subdiv_mesh::read_obj_with(&p, opts).unwrap_or_else(|e| panic!("{e}"));
            let name = p.file_stem().unwrap_or_default().to_string_lossy().into();
            (name, m)
        })
        .collect()
}

/// Pools of 1 and 2 threads: every case must hash the same on both.
fn pools() -> Vec<rayon::ThreadPool> {
    [1, 2]
        .map(|t| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .expect("thread pool")
        })
        .into()
}

/// Compares `now` with `tests/<file>` ([`subdiv_test_support::check_recorded`];
/// `SLATE_HASHES_BLESS` rewrites it).
fn check_recorded(file: &str, now: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join(file);
    subdiv_test_support::check_recorded(&path, now, "SLATE_HASHES_BLESS");
}

/// One line per case: `name depth points hash`, hashes of 1 and 2 threads and of a second run
/// into the same buffers on reused workers required equal.
fn lines() -> String {
    let pools = pools();
    let mut out = String::new();
    for (name, mesh) in cages() {
        // The largest case, tri_bunny_3k at depth 6, has 9.4 M points.
        for depth in 0..=MAX_DEPTH {
            let mut hashes = Vec::new();
            for pool in &pools {
                pool.install(|| {
                    let t = tessellate(&mesh, depth).expect("tessellation");
                    hashes.push((hash(&t), t.positions().len()));
                    if depth >= 1 {
                        let layout = PatchLayout::new(&mesh, depth).expect("layout");
                        let mut again = t.clone();
                        tessellate_layout_into(&mesh, &layout, &mut again).expect("tessellation");
                        hashes.push((hash(&again), again.positions().len()));
                    }
                });
            }
            // The scalar paths (what a CPU without AVX2 runs) give the same bits.
            if depth >= 2 {
                subdiv_slate::set_simd(false);
                let t = pools[1].install(|| tessellate(&mesh, depth).expect("tessellation"));
                subdiv_slate::set_simd(true);
                hashes.push((hash(&t), t.positions().len()));
            }
            assert!(
                hashes.iter().all(|h| *h == hashes[0]),
                "{name} depth {depth}: output depends on the thread count, on reuse or on SIMD: \
                 {hashes:x?}"
            );
            let (h, points) = hashes[0];
            writeln!(out, "{name} {depth} {points} {h:016x}").expect("write to a string");
        }
    }
    out
}

#[test]
fn output_is_bit_identical_to_the_recorded_hashes() {
    check_recorded("output_hashes.txt", &lines());
}

/// Deepest depth of the Loop cases.
const LOOP_MAX_DEPTH: subdiv_rules::Depth = 5;

/// The Loop slates' cases (every fixture cage of triangles, depths 1..=5, 1 and 2 threads and a
/// repeated run into the same buffers): one line `name depth points hash` each.
fn loop_lines() -> String {
    let pools = pools();
    let mut out = String::new();
    for (name, mesh) in cages() {
        // Cages Loop refuses (not triangles, doubled triangles) are not cases.
        if subdiv_slate::TriLayout::new(&mesh, 1).is_err() {
            continue;
        }
        for depth in 1..=LOOP_MAX_DEPTH {
            let mut hashes = Vec::new();
            for pool in &pools {
                pool.install(|| {
                    let t = subdiv_slate::tessellate_tri(&mesh, depth).expect("tessellation");
                    hashes.push((hash(&t), t.positions().len()));
                    let layout = subdiv_slate::TriLayout::new(&mesh, depth).expect("layout");
                    let mut again = t.clone();
                    subdiv_slate::tessellate_tri_layout_into(&mesh, &layout, &mut again)
                        .expect("tessellation");
                    hashes.push((hash(&again), again.positions().len()));
                });
            }
            assert!(
                hashes.iter().all(|h| *h == hashes[0]),
                "{name} depth {depth}: Loop output depends on the thread count or on reuse"
            );
            let (h, points) = hashes[0];
            writeln!(out, "{name} {depth} {points} {h:016x}").expect("write to a string");
        }
    }
    out
}

/// The Loop slates' output against `loop_output_hashes.txt`, recorded at commit d11c6ec (before
/// the Loop slates were sped up); same platform rule and `SLATE_HASHES_BLESS` as
/// above.
#[test]
fn loop_output_is_bit_identical_to_the_recorded_hashes() {
    check_recorded("loop_output_hashes.txt", &loop_lines());
}
