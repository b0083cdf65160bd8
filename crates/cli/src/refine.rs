//! `subdiv refine`: DoI-driven adaptive Loop subdivision (Isenberg, Hartmann & König 2003).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use subdiv::mesh::write_mesh_obj;
use subdiv::{OutputFormat, write_surface};

use crate::camera_args::CameraArgs;
use crate::choices::value_name;
use crate::doi_args::DoiArgs;
use crate::limit_args::LimitArgs;

#[derive(clap::Args, Debug)]
#[command(mut_arg("doi", |a| a.required(true)))]
pub struct RefineArgs {
    /// Input mesh: OBJ or USD (.usda, .usdc, .usdz); triangles, or any polygons with
    /// --triangulate.
    pub input: PathBuf,
    /// The USD mesh prim to read (e.g. /World/Body); every Mesh prim merged without it.
    #[arg(long, value_name = "PATH")]
    pub prim: Option<String>,
    /// USD: the time code to read the stage at (time samples interpolated as USD does)
    /// [default: default values, else the earliest time samples].
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub time: Option<f64>,
    #[command(flatten)]
    pub doi: DoiArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Output file, its format by extension: .obj (the refined mesh with its tags, UVs and
    /// vertex colours), .gltf (+ .bin) or .glb (glTF 2.0), .ply (binary); glTF and PLY hold the
    /// refined triangles with vertex normals, the cage's refined UVs when it has them
    /// (TEXCOORD_0, s t), its refined primvars (as `tessellate` writes them) and each vertex's
    /// largest DoI over its faces (_DOI, doi).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
    #[command(flatten)]
    pub limit: LimitArgs,
}

pub fn run(a: &RefineArgs) -> anyhow::Result<ExitCode> {
    let input = a.input.display().to_string();
    let format = OutputFormat::from_path(&a.output)?;
    let cage = crate::load::load_cage(&a.input, a.split_nonmanifold, a.prim.as_deref(), a.time)?;
    if format == OutputFormat::Obj {
        warn_primvars_beyond_obj(&cage.mesh, &a.output);
    }
    let setup = a.doi.setup(cage.mesh, &input)?;
    let steps = a.doi.steps;
    a.limit.check(
        &setup.cage,
        subdiv::rules::Request::Refine { steps },
        &input,
    )?;
    let (mesh, doi, threshold) = (&setup.cage, &setup.doi, setup.opts.threshold);
    let camera = a.camera.camera(mesh);
    let t0 = Instant::now();
    let spinner = crate::progress::spinner(format!("refining ({} steps)", a.doi.steps));
    let r = setup.run(camera);
    spinner.finish_and_clear();
    let r = r.with_context(|| format!("{input}: refining"))?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    if format == OutputFormat::Obj {
        let m = &r.mesh.mesh;
        let carried = m.whole_vertex_edges_all().map(|(v, _)| v);
        if let Some(v) = carried.chain(m.crease_ends_all().map(|(v, _)| v)).min() {
            // No OBJ tag says it: the file refines on as the pieces alone would.
            log::warn!(
                "{}: vertex {} (and others like it) is a copy of a non-manifold vertex that \
                 follows the whole vertex's rule (its semi-sharp edges, or crease edges its \
                 piece lacks); the OBJ cage cannot say so, and refines on differently from \
                 the cage it came from",
                a.output.display(),
                v.0
            );
        }
        write_mesh_obj(&a.output, &r.mesh.mesh)?;
    } else {
        write_surface(&a.output, &setup.refined_surface(&r, &camera)?)?;
    }
    out!(
        "refined {input} with the {} DoI (threshold {threshold}, {} steps, {}): {} -> {} triangles in {ms:.1} ms -> {}",
        doi.name(),
        a.doi.steps,
        value_name(&a.doi.aggregate),
        mesh.num_faces(),
        r.mesh.mesh.num_faces(),
        a.output.display()
    );
    for (i, s) in r.steps.iter().enumerate() {
        out!(
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

/// Warns that the OBJ cage written to `out` holds no primvar of `mesh` but its vertex colours
/// (a vertex `displayColor` of 3 floats).
fn warn_primvars_beyond_obj(mesh: &subdiv::mesh::Mesh, out: &std::path::Path) {
    let vertex_colour = |p: &subdiv::mesh::Primvar| {
        p.name == "displayColor"
            && p.width == 3
            && p.interpolation == subdiv::mesh::PrimvarInterpolation::Vertex
    };
    let left: Vec<&str> = mesh
        .primvars()
        .iter()
        .filter(|p| !vertex_colour(p))
        .map(|p| p.name.as_str())
        .collect();
    if !left.is_empty() {
        log::warn!(
            "{}: primvars {} are not written to an OBJ cage (it holds vertex colours only; \
             glTF and PLY hold every primvar)",
            out.display(),
            left.join(", ")
        );
    }
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

    #[test]
    fn quads_need_triangulate_and_focus_names_groups() {
        let input = temp("cube.obj", &subdiv_test_support::grouped_cube_obj());
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
        let m = subdiv::mesh::read_obj(&out).unwrap();
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
        // Focus objects with their own interest and skeleton; a bad value names the object.
        // A bone far below the cube: only the top's own faces stay interesting. Four steps: the
        // top's computed skeleton is its centre, and at interest 0.5 the sides' own steps only
        // show beyond the two that balancing around the top's refinement gives them anyway.
        let bone = temp("bone.txt", "0.5 0.5 -5\n0.5 0.5 -6\n");
        let top = format!("top={}", bone.display());
        let count = |focus: &[&str]| {
            let mut a = vec![
                i,
                "--doi",
                "focus",
                "--steps",
                "4",
                "--triangulate",
                "-o",
                o,
            ];
            a.extend_from_slice(focus);
            run(&args(&a)).map(|_| subdiv::mesh::read_obj(&out).unwrap().num_faces())
        };
        let full = count(&["--focus", "top"]).unwrap();
        let half = count(&["--focus", "top=0.5"]).unwrap();
        let with_bone = count(&["--focus", "top=0.5", "--skeleton", &top]).unwrap();
        assert!(half < full && with_bone < half, "{full} {half} {with_bone}");
        let e = count(&["--focus", "top=lots"]).unwrap_err();
        assert!(format!("{e:#}").contains("focus 'top=lots'"), "{e:#}");
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
