//! `subdiv info`.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use subdiv::mesh::{
    BoundaryInterpolation, CreaseMethod, Mesh, MeshStats, ObjError, StageTime, TriangleSubdivision,
    UsdReadOptions, UsdStageReader, is_usd_path, read_obj_soup,
};

#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// Input cage: OBJ with optional OpenSubdiv tags, or USD (.usda, .usdc, .usdz).
    pub input: PathBuf,
    /// The USD mesh prim to read (e.g. /World/Body); every Mesh prim merged without it.
    #[arg(long, value_name = "PATH")]
    pub prim: Option<String>,
    /// USD: the time code to read the stage at (time samples interpolated as USD does)
    /// [default: default values, else the earliest time samples].
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub time: Option<f64>,
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

/// The lines on a stage's time: `time range: start=S end=E time_codes_per_second=R (authored)`
/// (or `(from the time samples)`, or `time range: none (nothing is time-sampled)`), the
/// time-sampled attributes `time-sampled: /Prim.attr (N samples), ...`, and `time: T` when a
/// time was asked for.
fn time_lines(time: &StageTime, at: Option<f64>) -> String {
    const SHOWN: usize = 12;
    let mut out = String::new();
    match time.range() {
        Some((s, e)) => {
            let from = if time.authored.is_some() {
                "authored"
            } else {
                "from the time samples"
            };
            out += &format!(
                "time range: start={s} end={e} time_codes_per_second={} ({from})\n",
                time.time_codes_per_second
            );
        }
        None => out += "time range: none (nothing is time-sampled)\n",
    }
    if !time.sampled.is_empty() {
        let mut items: Vec<String> = time
            .sampled
            .iter()
            .take(SHOWN)
            .map(|(name, t)| format!("{name} ({} samples)", t.len()))
            .collect();
        if time.sampled.len() > SHOWN {
            items.push(format!("... {} more", time.sampled.len() - SHOWN));
        }
        out += &format!("time-sampled: {}\n", items.join(", "));
    }
    if let Some(t) = at {
        out += &format!("time: {t}\n");
    }
    out
}

/// `st faceVarying width 2 (24 values), displayColor vertex width 3 (8 values), ...`, or
/// `none`: the texture coordinates and every other primvar of `mesh`.
fn primvar_list(mesh: &Mesh) -> String {
    let mut items = Vec::new();
    if let Some(uv) = mesh.uv() {
        items.push(format!(
            "st faceVarying width 2 ({} values)",
            uv.values.len()
        ));
    }
    for p in mesh.primvars() {
        items.push(format!(
            "{} {} width {} ({} values)",
            p.name,
            p.interpolation.token(),
            p.width,
            p.num_values()
        ));
    }
    if items.is_empty() {
        "none".into()
    } else {
        items.join(", ")
    }
}

/// Prints the report; exits 1 (after the report) when the mesh would be refused.
pub fn run(a: &InfoArgs) -> anyhow::Result<ExitCode> {
    let path = a.input.display().to_string();
    let mut out = String::new();
    writeln!(out, "file: {path}")?;
    let mut soup = if is_usd_path(&a.input) {
        let opts = UsdReadOptions {
            prim: a.prim.clone(),
            ..UsdReadOptions::default()
        };
        let stage = UsdStageReader::open(&a.input, &opts)?;
        let usd = stage.read_soup_at(a.time)?;
        writeln!(out, "prims: {}", usd.prims.join(" "))?;
        writeln!(out, "subdivisionScheme: {}", usd.scheme.token())?;
        out.push_str(&time_lines(&stage.time()?, a.time));
        usd.soup
    } else {
        anyhow::ensure!(a.prim.is_none(), "{path}: --prim is for USD input");
        anyhow::ensure!(a.time.is_none(), "{path}: --time is for USD input");
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
    writeln!(out, "primvars: {}", primvar_list(&mesh))?;
    let loop_ok = s.face_sizes.keys().all(|&k| k == 3);
    writeln!(
        out,
        "schemes: catmull-clark yes, bilinear yes, loop {}",
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
