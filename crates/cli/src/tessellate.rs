//! `subdiv tessellate`: uniform (`--depth N`) or view-dependent adaptive (a camera, no `--depth`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, bail};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use subdiv::doi::DoiKind;
use subdiv::mesh::Mesh;
use subdiv::rules::{Request, Scheme};
use subdiv::stitch::AdaptiveFrame;
use subdiv::{
    DynamicSubdivision, OutputFormat, VertexScalar, depth_histogram, doi_face_depths, make_doi,
    write_surface,
};

use crate::adaptive_args::AdaptiveArgs;
use crate::camera_args::CameraArgs;
use crate::choices::{DoiName, SchemeName, value_name};
use crate::dicing_args::DicingArgs;
use crate::doi_args::{DoiChoice, doi_error};
use crate::limit_args::LimitArgs;

#[derive(clap::Args, Debug)]
#[command(mut_arg("doi", |a| a
    .help(
        "Drive the patch depths by a Degree-of-Interest function instead of the view \
         (face values above the threshold map linearly onto depths 1..max-depth)"
    )
    .value_parser(cage_doi_parser())))]
pub struct TessellateArgs {
    /// Input cage: OBJ with optional OpenSubdiv tags, or USD (.usda, .usdc, .usdz; every Mesh
    /// prim merged unless --prim names one).
    pub input: PathBuf,
    /// The USD mesh prim to read (e.g. /World/Body).
    #[arg(long, value_name = "PATH")]
    pub prim: Option<String>,
    /// USD: the time code to read the stage at (time samples interpolated as USD does)
    /// [default: default values, else the earliest time samples].
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub time: Option<f64>,
    /// Subdivision scheme [default: the USD subdivisionScheme, else catmull-clark].
    #[arg(long, value_enum)]
    pub scheme: Option<SchemeName>,
    /// Uniform subdivision depth (without it, a camera makes the tessellation adaptive).
    #[arg(long)]
    pub depth: Option<subdiv::rules::Depth>,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    #[command(flatten)]
    pub dicing: DicingArgs,
    #[command(flatten)]
    pub limit: LimitArgs,
    /// Print patches per depth, triangles and the uniform count at the maximum depth (with
    /// --dicing-rate: triangles and the edge rates).
    #[arg(long)]
    pub stats: bool,
    #[command(flatten)]
    pub doi: DoiChoice,
    /// Output file, its format by extension: .obj (limit positions, limit normals, faces),
    /// .gltf (+ .bin) or .glb (glTF 2.0), .ply (binary); glTF and PLY also carry each vertex's
    /// subdivision depth (_DEPTH, depth).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
}

/// `--doi` of `tessellate`: the DoIs that need neither a haptic interaction point nor Loop
/// refinement.
fn cage_doi_parser() -> impl TypedValueParser<Value = DoiName> {
    let kinds = [
        DoiKind::ViewAngle,
        DoiKind::Silhouette,
        DoiKind::Dihedral,
        DoiKind::Focus,
    ];
    PossibleValuesParser::new(kinds.map(DoiKind::name))
        .map(|s| <DoiName as clap::ValueEnum>::from_str(&s, false).expect("a DoI name"))
}

pub fn run(a: &TessellateArgs) -> anyhow::Result<ExitCode> {
    OutputFormat::from_path(&a.output)?;
    let cage = crate::load::load_cage(&a.input, a.split_nonmanifold, a.prim.as_deref(), a.time)?;
    let scheme = crate::load::cage_scheme(&a.input, &cage, a.scheme.map(Scheme::from))?;
    let mesh = cage.mesh;
    if let Some(d) = a.dicing.dicing()? {
        return run_dicing(a, &mesh, scheme, d);
    }
    let adaptive = a
        .adaptive
        .wants_adaptive(a.depth.is_some(), a.camera.has_camera(), &[])?;
    if let Some(depth) = a.depth {
        return run_uniform(a, &mesh, scheme, depth);
    }
    if !adaptive && a.doi.doi.is_none() {
        bail!(
            "give --depth N for a uniform tessellation, or a camera (--eye X,Y,Z or --eye-relative X,Y,Z) or an adaptive flag (--pixel-error PX, ...) for an adaptive one"
        );
    }
    run_adaptive(a, mesh, scheme)
}

/// `subdiv tessellate --depth N`.
fn run_uniform(
    a: &TessellateArgs,
    mesh: &Mesh,
    scheme: Scheme,
    depth: subdiv::rules::Depth,
) -> anyhow::Result<ExitCode> {
    let input = a.input.display();
    a.limit
        .check(mesh, Request::Uniform { scheme, depth }, &input.to_string())?;
    let t0 = Instant::now();
    let spinner = crate::progress::spinner(format!("tessellating at depth {depth}"));
    let t = subdiv::uniform_limit(mesh, scheme, depth);
    spinner.finish_and_clear();
    let t = t.map_err(|e| anyhow::anyhow!("{input}: {e}"))?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let mut t = t;
    t.set_scalar(VertexScalar::Depth, vec![depth as f32; t.num_vertices()])?;
    write_surface(&a.output, &t)?;
    out!(
        "tessellated {input}: {} vertices, {} faces ({}, depth {depth}) in {ms:.1} ms -> {}",
        t.num_vertices(),
        t.num_faces(),
        value_name(&SchemeName::from(scheme)),
        a.output.display()
    );
    if a.stats {
        out!("patches per depth: {depth}:{}", mesh.num_faces());
        out!("triangles: {}", t.triangles().len() / 3);
    }
    Ok(ExitCode::SUCCESS)
}

/// `subdiv tessellate --dicing-rate PX`: every cage edge's rate from its limit curve's length
/// on screen, the surface evaluated exactly at those rates.
fn run_dicing(
    a: &TessellateArgs,
    mesh: &Mesh,
    scheme: Scheme,
    d: subdiv::eval::Dicing,
) -> anyhow::Result<ExitCode> {
    let input = a.input.display().to_string();
    let mut given = a.adaptive.given();
    if a.depth.is_some() {
        given.push("--depth");
    }
    if a.doi.doi.is_some() {
        given.push("--doi");
    }
    if !given.is_empty() {
        bail!(
            "--dicing-rate chooses the tessellation itself: {} cannot go with it",
            given.join(", ")
        );
    }
    let t0 = Instant::now();
    let camera = a.camera.camera(mesh);
    let eval =
        subdiv::eval::Evaluator::new(mesh, scheme).map_err(|e| anyhow::anyhow!("{input}: {e}"))?;
    let mut t =
        subdiv::eval::dice(&eval, &camera, &d).map_err(|e| anyhow::anyhow!("{input}: {e}"))?;
    crate::load::dice_primvars(mesh, scheme, &mut t, &input)?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    write_surface(&a.output, &t.surface)?;
    let tris = t.surface.num_faces();
    out!(
        "tessellated {input}: {} vertices, {tris} triangles (dicing rate {} px, off-screen x{}) in {ms:.1} ms -> {}",
        t.surface.num_vertices(),
        d.rate_px,
        d.offscreen_scale,
        a.output.display()
    );
    if a.stats {
        out!("triangles: {tris}");
        out!("edge rates: {}", rate_summary(mesh, &t.rates));
    }
    Ok(ExitCode::SUCCESS)
}

/// `min=<n> median=<n> max=<n> mean=<f>` of the rates of the edges that are tessellated.
pub fn rate_summary(mesh: &Mesh, rates: &[u32]) -> String {
    let mut r: Vec<u32> = mesh
        .edges()
        .filter(|&e| {
            [e.halfedge(0), e.halfedge(1)]
                .iter()
                .any(|&h| mesh.face(h).is_some() && !mesh.is_hole(mesh.face(h)))
        })
        .map(|e| rates[e.idx()])
        .collect();
    r.sort_unstable();
    if r.is_empty() {
        return "none".into();
    }
    let mean = r.iter().map(|&x| f64::from(x)).sum::<f64>() / r.len() as f64;
    format!(
        "min={} median={} max={} mean={mean:.2}",
        r[0],
        r[r.len() / 2],
        r[r.len() - 1]
    )
}

/// `subdiv tessellate` with a camera or a DoI: the adaptive tessellation (Catmull-Clark or
/// Loop).
fn run_adaptive(a: &TessellateArgs, mesh: Mesh, scheme: Scheme) -> anyhow::Result<ExitCode> {
    let input = a.input.display().to_string();
    let max_depth = a.adaptive.max_depth();
    a.limit
        .check(&mesh, Request::Adaptive { scheme, max_depth }, &input)?;
    let t0 = Instant::now();
    let camera = a.camera.camera(&mesh);
    let doi_depths = match a.doi.doi {
        Some(name) => {
            let kind = DoiKind::from(name);
            let doi = make_doi(kind, &mesh, &a.doi.focus, &[], false)
                .map_err(|e| doi_error(e, &input))?;
            let depths = doi_face_depths(
                doi.as_ref(),
                &mesh,
                camera,
                a.doi.threshold,
                a.adaptive.max_depth(),
            )
            .with_context(|| format!("{input}: evaluating the {} DoI", kind.name()))?;
            Some(depths)
        }
        None => None,
    };
    let mut node = a
        .adaptive
        .node(mesh, scheme)
        .with_context(|| input.clone())?;
    node.set_face_depths(doi_depths)?;
    let spinner = crate::progress::spinner("adaptive tessellation");
    let g = node.update(&camera, None).map(|_| ());
    spinner.finish_and_clear();
    g?;
    node.carry_primvars()?;
    let g = node.geometry();
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    // The referenced vertices, the triangles with their one-sided corner normals, and the
    // depth of each vertex's patch.
    let limit = g.surface().referenced_only();
    write_surface(&a.output, &limit)?;
    out!(
        "tessellated {input}: {} vertices, {} triangles (adaptive, max depth {}) in {ms:.1} ms -> {}",
        limit.num_vertices(),
        limit.num_faces(),
        a.adaptive.max_depth(),
        a.output.display()
    );
    if a.stats {
        print_stats(a, &node, node.geometry());
    }
    Ok(ExitCode::SUCCESS)
}

/// `--stats` of the adaptive tessellation: patches per depth, triangles, and the uniform
/// counts it compares with.
fn print_stats(a: &TessellateArgs, node: &DynamicSubdivision, g: &AdaptiveFrame) {
    out!("patches per depth: {}", depth_histogram(g));
    let tris = g.num_triangles();
    let uni = node.uniform_triangles();
    out!("triangles: {tris}");
    out!(
        "uniform triangles at max depth {}: {uni} (adaptive/uniform = {:.3})",
        a.adaptive.max_depth(),
        tris as f64 / uni.max(1) as f64
    );
    if a.adaptive.pixel_error.is_some() {
        // Uniform tessellation with the same maximum screen error: every face at the deepest
        // depth any visible face needed.
        let asg = node.assignment();
        let dmax = asg
            .depth
            .iter()
            .zip(&asg.active)
            .filter(|(_, on)| **on)
            .map(|(d, _)| *d)
            .max()
            .unwrap_or(0);
        let u = node.uniform_triangles_at(dmax);
        out!(
            "uniform triangles at equal max screen error (depth {dmax}): {u} (adaptive/uniform = {:.3})",
            tris as f64 / u.max(1) as f64
        );
    }
}
