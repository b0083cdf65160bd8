//! `subdiv info`.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use subdiv::mesh::{
    BoundaryInterpolation, CreaseMethod, Mesh, MeshStats, ObjError, TriangleSubdivision,
    is_usd_path, read_obj_soup, read_usd_soup,
};

#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// Input cage: OBJ with optional OpenSubdiv tags, or USD (.usda, .usdc, .usdz).
    pub input: PathBuf,
    /// The USD mesh prim to read (e.g. /World/Body); every Mesh prim merged without it.
    #[arg(long, value_name = "PATH")]
    pub prim: Option<String>,
    /// Give each extra fan of faces at a non-manifold vertex its own vertex (the surface opens
    /// there) instead of refining non-manifold cages as OpenSubdiv does.
    #[arg(long)]
    pub split_nonmanifold: bool,
}

fn histogram(h: &std::collections::BTreeMap<usize, usize>) -> String {
    h.iter()
        .map(|(k, n)| format!("{k}:{n}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Prints the report; exits 1 (after the report) when the mesh would be refused.
pub fn run(a: &InfoArgs) -> anyhow::Result<ExitCode> {
    let path = a.input.display().to_string();
    let mut out = String::new();
    writeln!(out, "file: {path}")?;
    let mut soup = if is_usd_path(&a.input) {
        let usd = read_usd_soup(&a.input, a.prim.as_deref())?;
        writeln!(out, "prims: {}", usd.prims.join(" "))?;
        writeln!(out, "subdivisionScheme: {}", usd.scheme.token())?;
        usd.soup
    } else {
        anyhow::ensure!(a.prim.is_none(), "{path}: --prim is for USD input");
        read_obj_soup(&a.input)?
    };
    // Tag lines read but not applied: on stderr, in the report, and refused with --strict.
    let ignored = crate::load::report_tag_warnings(&a.input, &soup.warnings);
    if !soup.warnings.is_empty() {
        let list: Vec<String> = soup.warnings.iter().map(|w| w.short()).collect();
        writeln!(out, "ignored tags: {} ({})", list.len(), list.join(", "))?;
    }

    let prepared = if a.split_nonmanifold {
        let split = soup.split_nonmanifold_vertices();
        if !split.is_empty() {
            writeln!(out, "split non-manifold vertices: {}", split.len())?;
        }
        Ok(())
    } else {
        soup.split_nonmanifold().map(|found| {
            out.push_str(&crate::load::nonmanifold_lines(&found));
        })
    };
    let mesh = match prepared.and_then(|()| Mesh::from_soup(&soup)) {
        Ok(m) => m,
        Err(err) => {
            let mut sizes = std::collections::BTreeMap::new();
            for f in 0..soup.num_faces() {
                *sizes.entry(soup.face(f).len()).or_insert(0usize) += 1;
            }
            writeln!(out, "vertices: {}", soup.positions.len())?;
            writeln!(out, "faces: {}", soup.num_faces())?;
            writeln!(out, "face sizes: {}", histogram(&sizes))?;
            writeln!(out, "status: refused")?;
            crate::out::text(&out);
            let e = ObjError::Invalid { path, err };
            eprintln!("error: {e}");
            return Ok(ExitCode::FAILURE);
        }
    };
    let s = MeshStats::of(&mesh);
    let opts = mesh.options();
    writeln!(out, "vertices: {}", s.vertices)?;
    writeln!(out, "edges: {}", s.edges)?;
    writeln!(out, "faces: {}", s.faces)?;
    writeln!(out, "face sizes: {}", histogram(&s.face_sizes))?;
    writeln!(out, "valences: {}", histogram(&s.valences))?;
    writeln!(
        out,
        "max valence: {}",
        s.valences.keys().max().copied().unwrap_or(0)
    )?;
    writeln!(
        out,
        "boundary loops: {} ({} edges)",
        s.boundary_loops, s.boundary_edges
    )?;
    writeln!(
        out,
        "creases: {} semi-sharp edges (max sharpness {}), {} infinitely sharp edges",
        s.semi_sharp_edges, s.max_edge_sharpness, s.infinite_edges
    )?;
    writeln!(out, "sharp vertices: {}", s.sharp_vertices)?;
    writeln!(out, "holes: {}", s.holes)?;
    writeln!(out, "isolated vertices: {}", s.isolated_vertices)?;
    writeln!(out, "components: {}", s.components)?;
    writeln!(out, "euler characteristic: {}", s.euler)?;
    writeln!(out, "genus: {}", s.genus)?;
    let b = match opts.boundary {
        BoundaryInterpolation::None => "none",
        BoundaryInterpolation::EdgeOnly => "edge-only",
        BoundaryInterpolation::EdgeAndCorner => "edge-and-corner",
    };
    let c = match opts.crease {
        CreaseMethod::Uniform => "uniform",
        CreaseMethod::Chaikin => "chaikin",
    };
    let t = match opts.triangles {
        TriangleSubdivision::Catmark => "catmark",
        TriangleSubdivision::Smooth => "smooth",
    };
    writeln!(out, "options: boundary={b} crease={c} triangles={t}")?;
    if !mesh.groups().is_empty() {
        writeln!(out, "groups: {}", mesh.groups().join(", "))?;
    }
    let loop_ok = s.face_sizes.keys().all(|&k| k == 3);
    writeln!(
        out,
        "schemes: catmull-clark yes, loop {}",
        if loop_ok {
            "yes"
        } else {
            "no (faces other than triangles; use --triangulate)"
        }
    )?;
    if let Err(e) = ignored {
        // --strict: the mesh is fine, but it has tag lines subdiv does not apply.
        writeln!(out, "status: refused")?;
        crate::out::text(&out);
        eprintln!("error: {e}");
        return Ok(ExitCode::FAILURE);
    }
    writeln!(out, "status: ok")?;
    crate::out::text(&out);
    Ok(ExitCode::SUCCESS)
}
