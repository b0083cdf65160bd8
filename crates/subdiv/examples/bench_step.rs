//! Benchmark (not a test): time per step of silhouette-DoI adaptive Loop subdivision against
//! uniform Loop refinement of the same mesh, as cost per output triangle.
//!
//! ```sh
//! cargo run --release -p subdiv --example bench_step [-- MESH.obj [REPEATS]]
//! ```
//!
//! Defaults to `../shared/meshes/tri_armadillo_52k.obj` relative to the repository root and
//! skips with a message when it is absent.

use std::path::PathBuf;
use std::time::Instant;

use subdiv_doi::{Aggregate, DoiContext, Silhouette, face_values, select};
use subdiv_mesh::{Camera, ReadOptions, glam::Vec3, read_obj_with};
use subdiv_redgreen::{AdaptiveMesh, loop_step};
use subdiv_rules::{Scheme, refine_uniform};

/// The fastest run: on a shared machine the minimum is the least disturbed estimate.
fn best(v: Vec<f64>) -> f64 {
    v.into_iter().fold(f64::INFINITY, f64::min)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/meshes/tri_armadillo_52k.obj")
    });
    let repeats: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(5);
    if !path.exists() {
        println!("skipped: {} is absent", path.display());
        return;
    }
    let mesh = match read_obj_with(
        &path,
        ReadOptions {
            split_nonmanifold_vertices: true,
        },
    ) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
    let (lo, hi) = mesh.bounds();
    let cam = Camera::eye_relative(lo, hi, Vec3::new(0.0, 0.0, 3.0), 45.0, 800, 600);
    let ctx = DoiContext::with_camera(cam);
    println!(
        "{}: {} triangles; silhouette DoI (t = 0.5, max), camera --eye-relative 0,0,3; best of {repeats} runs",
        path.file_name()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_default(),
        mesh.num_faces()
    );
    println!();
    println!(
        "| step | uniform: in → out tris | uniform ms | ns/out tri | adaptive: in → out tris | DoI ms | step ms | total ms | ns/out tri | ratio |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut uni = mesh.clone();
    let mut ada = AdaptiveMesh::new(mesh).expect("a triangle mesh");
    let (mut scratch, mut values, mut sel) = (Vec::new(), Vec::new(), Vec::new());
    for step in 0..3u32 {
        // Uniform.
        let mut tu = Vec::new();
        let mut next_u = None;
        for _ in 0..repeats {
            let t = Instant::now();
            let m = refine_uniform(&uni, Scheme::Loop).expect("triangles");
            tu.push(t.elapsed().as_secs_f64());
            next_u = Some(m);
        }
        let next_u = next_u.expect("repeats > 0");
        // Adaptive: DoI evaluation + selection, then the step.
        let (mut td, mut ts) = (Vec::new(), Vec::new());
        let mut next_a = None;
        for _ in 0..repeats {
            let t = Instant::now();
            let c = DoiContext {
                step,
                steps: 3,
                ..ctx
            };
            face_values(
                &Silhouette,
                &ada.mesh,
                &c,
                Aggregate::Max,
                &mut scratch,
                &mut values,
            )
            .expect("camera");
            select(&values, 0.5, &mut sel);
            td.push(t.elapsed().as_secs_f64());
            let t = Instant::now();
            let (m, _) = loop_step(&ada, &sel).expect("valid");
            ts.push(t.elapsed().as_secs_f64());
            next_a = Some(m);
        }
        let next_a = next_a.expect("repeats > 0");
        let (mu, md, ms) = (best(tu), best(td), best(ts));
        let (nu, na) = (next_u.num_faces() as f64, next_a.mesh.num_faces() as f64);
        let per_u = mu * 1e9 / nu;
        let per_a = (md + ms) * 1e9 / na;
        println!(
            "| {} | {} → {} | {:.1} | {:.0} | {} → {} | {:.1} | {:.1} | {:.1} | {:.0} | {:.2} |",
            step + 1,
            uni.num_faces(),
            next_u.num_faces(),
            mu * 1e3,
            per_u,
            ada.mesh.num_faces(),
            next_a.mesh.num_faces(),
            md * 1e3,
            ms * 1e3,
            (md + ms) * 1e3,
            per_a,
            per_a / per_u
        );
        uni = next_u;
        ada = next_a;
    }
}
