//! `subdiv tessellate`: uniform (`--depth N`) or view-dependent adaptive (a camera, no `--depth`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, bail};
use subdiv_depth::DepthParams;
use subdiv_mesh::{ObjData, write_obj};
use subdiv_rules::{Scheme, tessellate_uniform};
use subdiv_slate::tessellate as slate_tessellate;
use subdiv::DynamicSubdivision;
use subdiv_stitch::FanMethod;

use crate::camera_args::CameraArgs;

/// Flags of the view-dependent depth assignment (shared with `render` and `view`).
#[derive(clap::Args, Debug, Clone)]
pub struct AdaptiveArgs {
    /// Deepest subdivision depth (`maxsd`).
    #[arg(long, default_value_t = 5)]
    pub max_depth: u8,
    /// Normal-cone aperture in degrees for the curvature depth.
    #[arg(long, default_value_t = 10.0)]
    pub cone_aperture: f32,
    /// Vertex classifier epsilon (back / front / silhouette).
    #[arg(long, default_value_t = 0.1)]
    pub classifier: f32,
    /// Projected sub-patch radius bounds in pixels.
    #[arg(long, value_parser = parse_pair, default_value = "2,8")]
    pub projected_size: (f32, f32),
    /// Choose the least depth whose chord error is at most PX pixels on screen.
    #[arg(long)]
    pub pixel_error: Option<f32>,
    /// Leave out back faces instead of drawing them at depth 0.
    #[arg(long)]
    pub cull_back: bool,
    /// Close depth transitions with plain fans (the paper's "simple method").
    #[arg(long)]
    pub simple_fans: bool,
}

impl AdaptiveArgs {
    /// The depth parameters these flags describe.
    pub fn params(&self) -> anyhow::Result<DepthParams> {
        if self.max_depth > 10 {
            bail!("--max-depth {} is too deep (at most 10)", self.max_depth);
        }
        if let Some(px) = self.pixel_error {
            if !(px.is_finite() && px > 0.0) {
                bail!("--pixel-error must be a positive number of pixels");
            }
        }
        Ok(DepthParams {
            max_depth: self.max_depth,
            cone_aperture_deg: self.cone_aperture,
            classifier_eps: self.classifier,
            projected_size: Some(self.projected_size),
            pixel_error: self.pixel_error,
            cull_back: self.cull_back,
        })
    }

    /// A ready node for `mesh`.
    pub fn node(&self, mesh: subdiv_mesh::Mesh) -> anyhow::Result<DynamicSubdivision> {
        let mut node = DynamicSubdivision::new(mesh, self.params()?)?;
        if self.simple_fans {
            node.set_fan_method(FanMethod::Simple);
        }
        Ok(node)
    }
}

/// Parses `A,B`.
pub fn parse_pair(s: &str) -> Result<(f32, f32), String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}' is not MIN,MAX"))?;
    let a: f32 = a
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not MIN,MAX"))?;
    let b: f32 = b
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not MIN,MAX"))?;
    if !(a.is_finite() && b.is_finite() && a > 0.0 && b >= a) {
        return Err(format!("'{s}': need 0 < MIN <= MAX"));
    }
    Ok((a, b))
}

#[derive(clap::Args, Debug)]
pub struct TessellateArgs {
    /// Input cage (OBJ with optional OpenSubdiv tags).
    pub input: PathBuf,
    /// Subdivision scheme.
    #[arg(long, default_value = "catmull-clark", value_parser = ["catmull-clark", "loop"])]
    pub scheme: String,
    /// Uniform subdivision depth (without it, a camera makes the tessellation adaptive).
    #[arg(long)]
    pub depth: Option<u32>,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub adaptive: AdaptiveArgs,
    /// Print patches per depth, triangles and the uniform count at the maximum depth.
    #[arg(long)]
    pub stats: bool,
    /// Drive the Catmull-Clark depths by a Degree-of-Interest function instead of the view
    /// (face values above the threshold map linearly onto depths 1..max-depth).
    #[arg(long, value_parser = ["view-angle", "silhouette", "dihedral", "focus"])]
    pub doi: Option<String>,
    /// DoI threshold (default: the DoI's figure value from the paper).
    #[arg(long, allow_hyphen_values = true)]
    pub threshold: Option<f32>,
    /// Focus objects (OBJ groups) for --doi focus.
    #[arg(long = "focus", value_name = "NAME")]
    pub focus: Vec<String>,
    /// Output OBJ (limit positions, limit normals, faces).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex instead of refusing.
    #[arg(long)]
    pub split_nonmanifold: bool,
}

/// The uniform limit tessellation at `depth` (shared by `tessellate`, `render` and `view`):
/// Catmull-Clark on the slate tessellator, Loop on the whole-mesh refinement.
pub fn uniform(
    mesh: &subdiv_mesh::Mesh,
    scheme: Scheme,
    depth: u32,
) -> Result<subdiv_rules::LimitMesh, Box<dyn std::error::Error + Send + Sync>> {
    Ok(match scheme {
        Scheme::CatmullClark => slate_tessellate(mesh, depth)?,
        Scheme::Loop => tessellate_uniform(mesh, scheme, depth)?,
    })
}

pub fn run(a: &TessellateArgs) -> anyhow::Result<ExitCode> {
    let scheme: Scheme = a.scheme.parse().map_err(anyhow::Error::msg)?;
    let mesh = crate::load::load_mesh(&a.input, a.split_nonmanifold)?;
    let input = a.input.display();
    let t0 = Instant::now();
    if let Some(depth) = a.depth {
        let t = uniform(&mesh, scheme, depth).map_err(|e| anyhow::anyhow!("{input}: {e}"))?;
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        write_obj(&a.output, &t.obj_data())?;
        println!(
            "tessellated {input}: {} vertices, {} faces ({}, depth {depth}) in {ms:.1} ms -> {}",
            t.positions.len(),
            t.num_faces(),
            a.scheme,
            a.output.display()
        );
        if a.stats {
            println!("patches per depth: {depth}:{}", mesh.num_faces());
            println!("triangles: {}", t.triangles().len() / 3);
        }
        return Ok(ExitCode::SUCCESS);
    }
    if !a.camera.has_camera() && a.doi.is_none() {
        bail!(
            "give --depth N for a uniform tessellation, or a camera (--eye X,Y,Z or --eye-relative X,Y,Z) for an adaptive one"
        );
    }
    if scheme != Scheme::CatmullClark {
        bail!(
            "adaptive tessellation with a camera is for --scheme catmull-clark; use `subdiv refine` for adaptive Loop"
        );
    }
    let (lo, hi) = mesh.bounds();
    let camera = a.camera.camera(lo, hi);
    let doi_depths = match &a.doi {
        Some(name) => {
            let doi =
                crate::refine::make_doi(name, &mesh, &a.focus, None, false, &input.to_string())?;
            let ctx = subdiv_doi::DoiContext {
                camera: Some(camera),
                ..Default::default()
            };
            let (mut scratch, mut values) = (Vec::new(), Vec::new());
            subdiv_doi::face_values(
                doi.as_ref(),
                &mesh,
                &ctx,
                subdiv_doi::Aggregate::Max,
                &mut scratch,
                &mut values,
            )
            .with_context(|| format!("{input}: evaluating the {name} DoI"))?;
            let t = a.threshold.unwrap_or(doi.default_threshold());
            Some(subdiv_depth::depths_from_face_values(
                &values,
                t,
                a.adaptive.max_depth,
            ))
        }
        None => None,
    };
    let mut node = a.adaptive.node(mesh).with_context(|| format!("{input}"))?;
    node.set_face_depths(doi_depths)?;
    let g = node.update(&camera, None)?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let (pos, nrm, idx) = g.compact();
    let offsets: Vec<u32> = (0..=idx.len() as u32 / 3).map(|i| i * 3).collect();
    write_obj(
        &a.output,
        &ObjData {
            positions: &pos,
            normals: Some(&nrm),
            face_offsets: &offsets,
            face_indices: &idx,
        },
    )?;
    println!(
        "tessellated {input}: {} vertices, {} triangles (adaptive, max depth {}) in {ms:.1} ms -> {}",
        pos.len(),
        idx.len() / 3,
        a.adaptive.max_depth,
        a.output.display()
    );
    if a.stats {
        let per = g.units_per_depth();
        let per: Vec<String> = per
            .iter()
            .enumerate()
            .map(|(d, n)| format!("{d}:{n}"))
            .collect();
        let culled = g.unit_depth.iter().filter(|&&d| d == u8::MAX).count();
        println!(
            "patches per depth: {}{}",
            per.join(" "),
            if culled > 0 {
                format!(" culled:{culled}")
            } else {
                String::new()
            }
        );
        let tris = g.num_triangles();
        let uni = node.uniform_triangles();
        println!("triangles: {tris}");
        println!(
            "uniform triangles at max depth {}: {uni} (adaptive/uniform = {:.3})",
            a.adaptive.max_depth,
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
            println!(
                "uniform triangles at equal max screen error (depth {dmax}): {u} (adaptive/uniform = {:.3})",
                tris as f64 / u.max(1) as f64
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
