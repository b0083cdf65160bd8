//! `cargo xtask figures`, DoI part: reproduces the triangle table and the silhouette comparison
//! of Isenberg, Hartmann & König, "Interest Value Driven Adaptive Subdivision" (2003), §4.1
//! (Figs. 3–5), on the fixture meshes. The measurements go to `docs/figures/doi_*.csv`; the
//! section of `docs/figures.md` (between markers, so other sections of the file are kept) is
//! generated from those files by `figures_doi_text.rs`.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use glam::Vec3;
use subdiv::{Balance, RefineOptions, refine_adaptive};
use subdiv_doi::{
    Aggregate, Curvature, Dihedral, Doi, DoiContext, Haptic, HapticPoint, Silhouette, ViewAngle,
    closest_surface_point, silhouette_distance, silhouette_segments,
};
use subdiv_mesh::{Camera, Mesh, ReadOptions, read_obj_with};
use subdiv_rules::{Scheme, refine_uniform_levels};

use crate::figures_doi_text::{DoiData, FOV, SIZE, STEPS};
use crate::figures_table::Table;

/// "In both cases the model is viewed directly from the front."
const EYE_RELATIVE: Vec3 = Vec3::new(0.0, 0.0, 3.0);

/// One DoI after 5 steps: its name, the smallest angle and the triangle count, each for the
/// plain closure and balanced.
type Quality = (&'static str, [f32; 2], [usize; 2]);

struct Row {
    model: String,
    input: usize,
    uniform: usize,
    /// Balanced (the default) counts of view angle, silhouette, dihedral.
    counts: [usize; 3],
    /// The same without balancing (the paper's plain closure).
    plain: [usize; 3],
    per_step: [Vec<usize>; 3],
    silhouette: [f32; 6],
    /// Haptic, haptic point, curvature max / avg / min.
    others: [usize; 5],
    /// Smallest angle of the input, then per DoI after 5 steps: (plain, balanced).
    quality: (f32, Vec<Quality>),
}

fn load(root: &Path, name: &str) -> Result<Mesh> {
    let p = root.join("fixtures/meshes").join(name);
    read_obj_with(
        &p,
        ReadOptions {
            split_nonmanifold_vertices: true,
        },
    )
    .with_context(|| format!("reading {}", p.display()))
}

fn measure(root: &Path, name: &str) -> Result<Row> {
    let mesh = load(root, name)?;
    let (lo, hi) = mesh.bounds();
    let cam = Camera::eye_relative(lo, hi, EYE_RELATIVE, FOV, SIZE.0, SIZE.1);
    // The haptic interaction point touches the surface: a bounding-box point snapped to it.
    let hip = lo + (hi - lo) * Vec3::new(0.9, 0.6, 0.5);
    let hip = closest_surface_point(&mesh, hip).map_or(hip, |x| x.1);
    let ctx = DoiContext {
        camera: Some(cam),
        hip: Some(hip),
        ..Default::default()
    };
    let uniform = refine_uniform_levels(&mesh, Scheme::Loop, STEPS as subdiv::rules::Depth)?;
    let go = |doi: &dyn Doi, steps, aggregate, balance| -> Result<(usize, Vec<usize>, Mesh)> {
        let opts = RefineOptions {
            threshold: doi.default_threshold(),
            steps,
            aggregate,
            balance,
        };
        let r = refine_adaptive(&mesh, doi, &ctx, &opts)?;
        Ok((
            r.mesh.mesh.num_faces(),
            r.steps.iter().map(|s| s.triangles).collect(),
            r.mesh.mesh,
        ))
    };
    let run = |doi: &dyn Doi| go(doi, STEPS, Aggregate::Max, Balance::Vertex);
    let plain =
        |doi: &dyn Doi| Ok::<_, anyhow::Error>(go(doi, STEPS, Aggregate::Max, Balance::None)?.0);
    let (va, va_steps, _) = run(&ViewAngle)?;
    let (si, si_steps, si_mesh) = run(&Silhouette)?;
    let (di, di_steps, _) = run(&Dihedral)?;
    let plain_counts = [plain(&ViewAngle)?, plain(&Silhouette)?, plain(&Dihedral)?];
    let haptic = Haptic::for_mesh(&mesh, Haptic::DEFAULT_TOLERANCE);
    let (hg, _, _) = run(&haptic)?;
    let (hp, _, _) = run(&HapticPoint)?;
    let curv = |agg| Ok::<_, anyhow::Error>(go(&Curvature, STEPS, agg, Balance::Vertex)?.0);
    let cu = [
        curv(Aggregate::Max)?,
        curv(Aggregate::Avg)?,
        curv(Aggregate::Min)?,
    ];
    let mut quality = Vec::new();
    let dois: [&dyn Doi; 6] = [
        &ViewAngle,
        &Silhouette,
        &Dihedral,
        &haptic,
        &HapticPoint,
        &Curvature,
    ];
    for doi in dois {
        let angle = |b| {
            let m = go(doi, 5, Aggregate::Max, b)?.2;
            Ok::<_, anyhow::Error>((min_angle(&m), m.num_faces()))
        };
        let (p, b) = (angle(Balance::None)?, angle(Balance::Vertex)?);
        quality.push((doi.name(), [p.0, b.0], [p.1, b.1]));
    }

    // Fig. 5: silhouettes of the adaptive and the uniform mesh, in pixels.
    let s_uni = silhouette_segments(&uniform, &cam);
    let s_ada = silhouette_segments(&si_mesh, &cam);
    let s_cage = silhouette_segments(&mesh, &cam);
    let (max_au, mean_au) = silhouette_distance(&s_ada, &s_uni, 0.25);
    let (max_ua, mean_ua) = silhouette_distance(&s_uni, &s_ada, 0.25);
    let (max_cu, mean_cu) = silhouette_distance(&s_cage, &s_uni, 0.25);
    Ok(Row {
        model: name.trim_end_matches(".obj").to_string(),
        input: mesh.num_faces(),
        uniform: uniform.num_faces(),
        counts: [va, si, di],
        plain: plain_counts,
        per_step: [va_steps, si_steps, di_steps],
        silhouette: [
            max_au.max(max_ua),
            mean_au.max(mean_ua),
            max_cu,
            mean_cu,
            s_ada.len() as f32,
            s_uni.len() as f32,
        ],
        others: [hg, hp, cu[0], cu[1], cu[2]],
        quality: (min_angle(&mesh), quality),
    })
}

/// The smallest corner angle of a triangle mesh, in degrees.
pub(crate) fn min_angle(m: &Mesh) -> f32 {
    let mut worst = 180.0f32;
    for f in m.faces() {
        let v = m.face_vertices(f);
        for k in 0..3 {
            let a = m.position(v[k]);
            let b = m.position(v[(k + 1) % 3]);
            let c = m.position(v[(k + 2) % 3]);
            worst = worst.min((b - a).angle_between(c - a).to_degrees());
        }
    }
    worst
}

/// The measured rows as the DoI tables (`focus`: the §4.3 table).
fn tables(rows: &[Row], focus: Table) -> DoiData {
    let n = |x: usize| x.to_string();
    let mut counts = Table::new(&[
        "model",
        "input",
        "uniform",
        "view_angle_plain",
        "view_angle",
        "silhouette_plain",
        "silhouette",
        "dihedral_plain",
        "dihedral",
        "haptic",
        "haptic_point",
        "curvature_max",
        "curvature_avg",
        "curvature_min",
    ]);
    let mut steps = Table::new(&["model", "doi", "step", "triangles"]);
    let mut silhouette = Table::new(&[
        "model",
        "doi_max_px",
        "doi_mean_px",
        "input_max_px",
        "input_mean_px",
        "segments_adaptive",
        "segments_uniform",
    ]);
    let mut angles = Table::new(&[
        "model",
        "doi",
        "plain_deg",
        "balanced_deg",
        "plain_triangles",
        "balanced_triangles",
    ]);
    for r in rows {
        let mut c = vec![r.model.clone(), n(r.input), n(r.uniform)];
        for k in 0..3 {
            c.extend([n(r.plain[k]), n(r.counts[k])]);
        }
        c.extend(r.others.iter().map(|&x| n(x)));
        counts.push(c);
        for (doi, v) in ["view_angle", "silhouette", "dihedral"]
            .iter()
            .zip(&r.per_step)
        {
            for (i, t) in v.iter().enumerate() {
                steps.push(vec![r.model.clone(), doi.to_string(), n(i + 1), n(*t)]);
            }
        }
        let mut sil = vec![r.model.clone()];
        sil.extend(r.silhouette.iter().map(|x| x.to_string()));
        silhouette.push(sil);
        let (input, q) = &r.quality;
        angles.push(vec![
            r.model.clone(),
            "input".into(),
            input.to_string(),
            input.to_string(),
            r.input.to_string(),
            r.input.to_string(),
        ]);
        for (name, [p, b], [tp, tb]) in q {
            angles.push(vec![
                r.model.clone(),
                name.to_string(),
                p.to_string(),
                b.to_string(),
                tp.to_string(),
                tb.to_string(),
            ]);
        }
    }
    DoiData {
        counts,
        steps,
        silhouette,
        angles,
        focus,
    }
}

/// Computes the DoI figures, writes their CSV files and the DoI section of `docs/figures.md`.
pub fn run(root: &Path) -> Result<()> {
    let t0 = Instant::now();
    let models = ["tri_teapot.obj", "tri_bunny_3k.obj"];
    let bar = crate::progress(models.len() as u64, "figures doi");
    let rows = models
        .iter()
        .map(|n| {
            bar.set_message(*n);
            let row = measure(root, n);
            bar.inc(1);
            row
        })
        .collect::<Result<Vec<_>>>();
    bar.finish_and_clear();
    let rows = rows?;
    let data = tables(&rows, crate::figures_focus::measure(root)?);
    let dir = root.join("docs/figures");
    std::fs::create_dir_all(&dir)?;
    data.write(&dir)?;
    let s = crate::figures_doi_text::markdown(&data)?;
    let path = root.join("docs/figures.md");
    crate::figures_cc::splice_into_doc(
        &path,
        crate::figures_doi_text::BEGIN,
        crate::figures_doi_text::END,
        &s,
    )?;
    println!(
        "figures (DoI): wrote docs/figures/doi_*.csv and {} in {:.1} s",
        path.display(),
        t0.elapsed().as_secs_f64()
    );
    print!("{s}");
    Ok(())
}
