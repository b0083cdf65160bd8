//! `subdiv refine`: DoI-driven adaptive Loop subdivision (Isenberg, Hartmann & König 2003).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use glam::Vec3;
use subdiv::{RefineOptions, refine_adaptive};
use subdiv_doi::{
    Aggregate, Dihedral, Doi, DoiContext, Focus, HapticG1, HapticPoint, Silhouette, ViewAngle,
    read_skeleton,
};
use subdiv_mesh::{triangulate, write_mesh_obj};

use crate::camera_args::{CameraArgs, parse_vec3};

#[derive(clap::Args, Debug)]
pub struct RefineArgs {
    /// Input mesh (OBJ; triangles, or any polygons with --triangulate).
    pub input: PathBuf,
    /// The Degree-of-Interest function.
    #[arg(long, value_parser = ["view-angle", "silhouette", "dihedral", "haptic", "focus"])]
    pub doi: String,
    /// Refine faces whose DoI exceeds this (default: the paper's figure value: view-angle 70
    /// (degrees from head-on), silhouette 0.5, dihedral 30 (degrees), haptic 0.5, focus 0).
    #[arg(long, allow_hyphen_values = true)]
    pub threshold: Option<f32>,
    /// Number of adaptive steps.
    #[arg(long, default_value_t = 3)]
    pub steps: u32,
    /// How edge or vertex values become face values.
    #[arg(long, default_value = "max", value_parser = ["max", "avg", "min"])]
    pub aggregate: String,
    /// Split quads and n-gons into triangles first (Loop subdivision needs triangles).
    #[arg(long)]
    pub triangulate: bool,
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Focus objects (OBJ group or object names) for --doi focus; repeatable.
    #[arg(long = "focus", value_name = "NAME")]
    pub focus: Vec<String>,
    /// Skeleton polyline for --doi focus (points as `v X Y Z` or `X Y Z` lines).
    #[arg(long)]
    pub skeleton: Option<PathBuf>,
    /// Haptic interaction point: with --doi haptic, refine the triangle closest to it and its
    /// one-neighbourhood instead of using the Clough-Tocher G1 error.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub hip: Option<Vec3>,
    /// Output OBJ.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex instead of refusing.
    #[arg(long)]
    pub split_nonmanifold: bool,
}

/// The DoI named `name` for `mesh` (shared by `refine` and `tessellate --doi`).
pub fn make_doi(
    name: &str,
    mesh: &subdiv_mesh::Mesh,
    focus: &[String],
    skeleton: Option<&std::path::Path>,
    hip: bool,
    input: &str,
) -> anyhow::Result<Box<dyn Doi>> {
    Ok(match name {
        "view-angle" => Box::new(ViewAngle),
        "silhouette" => Box::new(Silhouette),
        "dihedral" => Box::new(Dihedral),
        "haptic" if hip => Box::new(HapticPoint),
        "haptic" => Box::new(HapticG1),
        "focus" => {
            let skeleton = match skeleton {
                Some(p) => Some(read_skeleton(p)?),
                None => None,
            };
            Box::new(
                Focus::from_groups(mesh, focus, skeleton, Focus::default_radius(mesh))
                    .with_context(|| format!("{input}: --focus"))?,
            )
        }
        other => anyhow::bail!("unknown DoI '{other}'"),
    })
}

/// Refuses DoI options that the chosen DoI (`doi`, `None` for no DoI at all) would ignore
/// (shared by `refine` and `render --doi`).
pub fn check_doi_options(
    doi: Option<&str>,
    focus: &[String],
    skeleton: Option<&std::path::Path>,
    hip: Option<Vec3>,
) -> anyhow::Result<()> {
    if doi != Some("focus") && (!focus.is_empty() || skeleton.is_some()) {
        anyhow::bail!("--focus and --skeleton need --doi focus");
    }
    if hip.is_some() && doi != Some("haptic") {
        anyhow::bail!("--hip needs --doi haptic");
    }
    Ok(())
}

/// A DoI-driven refinement as the DoI flags describe it, ready to run for a camera: the
/// triangle cage (split with `--triangulate`), the DoI and the refinement options. Shared by
/// `refine`, `render --doi` and `view --doi`, so the three treat their flags alike.
pub struct DoiRefinement {
    /// The triangle mesh refined.
    pub cage: subdiv_mesh::Mesh,
    /// The Degree-of-Interest function.
    pub doi: Box<dyn Doi>,
    /// Haptic interaction point (`--hip`).
    pub hip: Option<Vec3>,
    /// Threshold, steps and aggregation.
    pub opts: RefineOptions,
}

/// The DoI flags shared by `refine` and `render`/`view --doi`.
pub struct DoiFlags<'a> {
    pub doi: &'a str,
    pub threshold: Option<f32>,
    pub steps: u32,
    pub aggregate: &'a str,
    pub triangulate: bool,
    pub focus: &'a [String],
    pub skeleton: Option<&'a std::path::Path>,
    pub hip: Option<Vec3>,
}

impl DoiRefinement {
    /// Checks the flags against each other and against `mesh` (read from `input`), and builds
    /// the DoI.
    pub fn new(
        mut mesh: subdiv_mesh::Mesh,
        input: &str,
        f: &DoiFlags<'_>,
    ) -> anyhow::Result<DoiRefinement> {
        check_doi_options(Some(f.doi), f.focus, f.skeleton, f.hip)?;
        if f.triangulate {
            mesh = triangulate(&mesh).with_context(|| format!("{input}: triangulating"))?;
        } else if let Some(face) = mesh.faces().find(|&x| mesh.face_size(x) != 3) {
            anyhow::bail!(
                "{input}: face {} has {} vertices; Loop subdivision needs triangles (pass --triangulate to split quads and n-gons)",
                face.0,
                mesh.face_size(face)
            );
        }
        let doi = make_doi(f.doi, &mesh, f.focus, f.skeleton, f.hip.is_some(), input)?;
        let threshold = f.threshold.unwrap_or(doi.default_threshold());
        if !threshold.is_finite() {
            anyhow::bail!("--threshold must be a finite number");
        }
        let aggregate: Aggregate = f.aggregate.parse().map_err(anyhow::Error::msg)?;
        Ok(DoiRefinement {
            cage: mesh,
            doi,
            hip: f.hip,
            opts: RefineOptions {
                threshold,
                steps: f.steps,
                aggregate,
            },
        })
    }

    /// The evaluation context for `camera`.
    pub fn context(&self, camera: subdiv_mesh::Camera) -> DoiContext {
        DoiContext {
            camera: Some(camera),
            hip: self.hip,
            ..Default::default()
        }
    }

    /// Refines the cage for `camera`.
    pub fn run(&self, camera: subdiv_mesh::Camera) -> anyhow::Result<subdiv::Refined> {
        Ok(refine_adaptive(
            &self.cage,
            self.doi.as_ref(),
            &self.context(camera),
            &self.opts,
        )?)
    }
}

pub fn run(a: &RefineArgs) -> anyhow::Result<ExitCode> {
    let input = a.input.display().to_string();
    let mesh = crate::load::load_mesh(&a.input, a.split_nonmanifold)?;
    let setup = DoiRefinement::new(
        mesh,
        &input,
        &DoiFlags {
            doi: &a.doi,
            threshold: a.threshold,
            steps: a.steps,
            aggregate: &a.aggregate,
            triangulate: a.triangulate,
            focus: &a.focus,
            skeleton: a.skeleton.as_deref(),
            hip: a.hip,
        },
    )?;
    let (lo, hi) = setup.cage.bounds();
    let (mesh, doi, threshold) = (&setup.cage, &setup.doi, setup.opts.threshold);
    let t0 = Instant::now();
    let r = setup
        .run(a.camera.camera(lo, hi))
        .with_context(|| format!("{input}: refining"))?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    write_mesh_obj(&a.output, &r.mesh.mesh)?;
    println!(
        "refined {input} with the {} DoI (threshold {threshold}, {} steps, {}): {} -> {} triangles in {ms:.1} ms -> {}",
        doi.name(),
        a.steps,
        a.aggregate,
        mesh.num_faces(),
        r.mesh.mesh.num_faces(),
        a.output.display()
    );
    for (i, s) in r.steps.iter().enumerate() {
        println!(
            "  step {}: {} selected, {} refined, {} merged back, {} triangles ({} green)",
            i + 1,
            s.selected,
            s.refined,
            s.merged,
            s.triangles,
            s.green
        );
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: RefineArgs,
    }

    fn temp(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("subdiv-refine-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    fn args(v: &[&str]) -> RefineArgs {
        Cli::try_parse_from(std::iter::once("refine").chain(v.iter().copied()))
            .unwrap()
            .args
    }

    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
        g bottom\nf 1 3 4 2\ng top\nf 5 6 8 7\ng sides\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

    #[test]
    fn quads_need_triangulate_and_focus_names_groups() {
        let input = temp("cube.obj", CUBE);
        let out = input.with_file_name("out.obj");
        let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());
        let e = run(&args(&[i, "--doi", "dihedral", "-o", o]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("cube.obj: face 0 has 4 vertices"), "{e}");
        assert!(e.contains("--triangulate"), "{e}");
        run(&args(&[
            i,
            "--doi",
            "dihedral",
            "--triangulate",
            "--steps",
            "2",
            "-o",
            o,
        ]))
        .unwrap();
        let m = subdiv_mesh::read_obj(&out).unwrap();
        assert!(m.num_faces() > 12 && m.num_faces() <= 12 * 16);
        let e = run(&args(&[
            i,
            "--doi",
            "focus",
            "--focus",
            "lid",
            "--triangulate",
            "-o",
            o,
        ]))
        .unwrap_err();
        let msg = format!("{e:#}");
        assert!(
            msg.contains("no group or object named 'lid'")
                && msg.contains("available: bottom, top, sides"),
            "{msg}"
        );
        run(&args(&[
            i,
            "--doi",
            "focus",
            "--focus",
            "top",
            "--triangulate",
            "-o",
            o,
        ]))
        .unwrap();
        let e = run(&args(&[
            i,
            "--doi",
            "silhouette",
            "--hip",
            "0,0,0",
            "--triangulate",
            "-o",
            o,
        ]))
        .unwrap_err();
        assert!(e.to_string().contains("--hip needs --doi haptic"));
        run(&args(&[
            i,
            "--doi",
            "haptic",
            "--hip",
            "0.5,0.5,1.2",
            "--triangulate",
            "-o",
            o,
        ]))
        .unwrap();
        run(&args(&[
            i,
            "--doi",
            "view-angle",
            "--eye-relative",
            "0,0,3",
            "--triangulate",
            "-o",
            o,
        ]))
        .unwrap();
    }
}
