//! `subdiv tessellate`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use subdiv_mesh::write_obj;
use subdiv_rules::{tessellate_uniform, Scheme};
use subdiv_slate::tessellate as slate_tessellate;

#[derive(clap::Args, Debug)]
pub struct TessellateArgs {
    /// Input cage (OBJ with optional OpenSubdiv tags).
    pub input: PathBuf,
    /// Subdivision scheme.
    #[arg(long, default_value = "catmull-clark", value_parser = ["catmull-clark", "loop"])]
    pub scheme: String,
    /// Uniform subdivision depth.
    #[arg(long)]
    pub depth: u32,
    /// Output OBJ (limit positions, limit normals, faces).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex instead of refusing.
    #[arg(long)]
    pub split_nonmanifold: bool,
}

pub fn run(a: &TessellateArgs) -> anyhow::Result<ExitCode> {
    let scheme: Scheme = a.scheme.parse().map_err(anyhow::Error::msg)?;
    let mesh = crate::load::load_mesh(&a.input, a.split_nonmanifold)?;
    let t0 = Instant::now();
    let t = match scheme {
        // Catmull-Clark runs on the slate tessellator; Loop on the whole-mesh refinement.
        Scheme::CatmullClark => slate_tessellate(&mesh, a.depth).map_err(|e| anyhow::anyhow!("{}: {e}", a.input.display()))?,
        Scheme::Loop => tessellate_uniform(&mesh, scheme, a.depth).map_err(|e| anyhow::anyhow!("{}: {e}", a.input.display()))?,
    };
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    write_obj(&a.output, &t.obj_data())?;
    println!(
        "tessellated {}: {} vertices, {} faces ({}, depth {}) in {:.1} ms -> {}",
        a.input.display(),
        t.positions.len(),
        t.num_faces(),
        a.scheme,
        a.depth,
        ms,
        a.output.display()
    );
    Ok(ExitCode::SUCCESS)
}
