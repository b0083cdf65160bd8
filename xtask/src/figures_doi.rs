//! `cargo xtask figures`, DoI part: reproduces the triangle table and the silhouette comparison
//! of Isenberg, Hartmann & König, "Interest Value Driven Adaptive Subdivision" (2003), §4.1
//! (Figs. 3–5), on the fixture meshes, and writes them as a section of `docs/figures.md`
//! (between markers, so other sections of the file are kept).

use std::fmt::Write as _;
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

const BEGIN: &str = "<!-- figures:doi:begin -->";
const END: &str = "<!-- figures:doi:end -->";

/// The paper's model: 902 triangles, 3 steps.
const PAPER: [(&str, u64); 4] = [
    ("uniform", 57_728),
    ("view angle", 26_872),
    ("silhouette", 11_188),
    ("dihedral", 4_532),
];
const PAPER_INPUT: u64 = 902;
const STEPS: u32 = 3;
/// "In both cases the model is viewed directly from the front."
const EYE_RELATIVE: Vec3 = Vec3::new(0.0, 0.0, 3.0);
const FOV: f32 = 45.0;
const SIZE: (u32, u32) = (800, 600);

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
    /// Smallest angle of the input, then per DoI after 5 steps.
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

fn pct(n: u64, d: u64) -> String {
    format!("{:.1} %", 100.0 * n as f64 / d as f64)
}

fn thousands(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Computes the DoI figures and writes the DoI section of `docs/figures.md`.
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
    let mut s = String::new();
    writeln!(s, "{BEGIN}")?;
    writeln!(
        s,
        "## Degree-of-Interest adaptive Loop subdivision (Isenberg, Hartmann & König 2003)\n"
    )?;
    writeln!(
        s,
        "Generated by `cargo xtask figures` (`xtask/src/figures_doi.rs`). {STEPS} steps of adaptive Loop \
         subdivision with red-green closure (`subdiv-doi`, `subdiv-loop`), balanced by default (faces sharing a \
         vertex differ by at most one level; `--no-balance` for the paper's plain closure), each DoI at its \
         default threshold (the paper's figure values: view angle: faces within 20° of edge-on, i.e. value \
         `acos|n·v|` > 70°; silhouette edges, eq. (2), t = 0.5; dihedral angle > 30°, concave edges 0), \
         edge values aggregated to faces by max. Camera: `--eye-relative 0,0,3` (\"viewed directly from the \
         front\"), {FOV}° vertical field of view, {}x{} pixels. Equivalent command line: \
         `subdiv refine fixtures/meshes/MODEL.obj --split-nonmanifold --doi DOI --steps 3 --eye-relative 0,0,3 -o OUT.obj`.\n",
        SIZE.0, SIZE.1
    )?;
    writeln!(
        s,
        "### Triangle counts after {STEPS} steps (paper §4.1, Figs. 3 and 4)\n"
    )?;
    writeln!(
        s,
        "| model | input | uniform Loop | view angle (Fig. 3a) | silhouette (Fig. 3b) | dihedral (Fig. 4) |"
    )?;
    writeln!(s, "|---|---:|---:|---:|---:|---:|")?;
    writeln!(
        s,
        "| paper (902-triangle model) | {PAPER_INPUT} | {} | {} ({}) | {} ({}) | {} ({}) |",
        thousands(PAPER[0].1),
        thousands(PAPER[1].1),
        pct(PAPER[1].1, PAPER[0].1),
        thousands(PAPER[2].1),
        pct(PAPER[2].1, PAPER[0].1),
        thousands(PAPER[3].1),
        pct(PAPER[3].1, PAPER[0].1)
    )?;
    for r in &rows {
        let u = r.uniform as u64;
        let cell = |k: usize| {
            let (p, b) = (r.plain[k] as u64, r.counts[k] as u64);
            format!(
                "{} ({}) / {} ({:+.0} %)",
                thousands(p),
                pct(p, u),
                thousands(b),
                100.0 * (b as f64 / p as f64 - 1.0)
            )
        };
        writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r.model,
            r.input,
            thousands(u),
            cell(0),
            cell(1),
            cell(2)
        )?;
    }
    writeln!(
        s,
        "\nModel rows: the paper's plain red-green closure (percentage of uniform Loop) / with level \
         balancing (the default) and, in parentheses, the triangle-count cost of balancing. The plain \
         counts are the ones to compare with the paper's row. Triangles after each step (balanced):\n"
    )?;
    writeln!(s, "| model | view angle | silhouette | dihedral |")?;
    writeln!(s, "|---|---|---|---|")?;
    for r in &rows {
        let f = |v: &Vec<usize>| {
            v.iter()
                .map(|x| thousands(*x as u64))
                .collect::<Vec<_>>()
                .join(" → ")
        };
        writeln!(
            s,
            "| {} | {} | {} | {} |",
            r.model,
            f(&r.per_step[0]),
            f(&r.per_step[1]),
            f(&r.per_step[2])
        )?;
    }
    writeln!(s, "\n### Silhouette quality (paper Fig. 5)\n")?;
    writeln!(
        s,
        "Silhouette edges (eq. (2)) of the {STEPS}-step meshes projected to pixels; each polyline is sampled every \
         0.25 px and the distance to the nearest segment of the other is taken, both ways (symmetric: the larger \
         of the two directions). No visibility test: hidden silhouette edges count too.\n"
    )?;
    writeln!(
        s,
        "| model | silhouette DoI vs uniform: max | mean | input mesh vs uniform: max | mean | segments (adaptive / uniform) |"
    )?;
    writeln!(s, "|---|---:|---:|---:|---:|---:|")?;
    for r in &rows {
        let q = &r.silhouette;
        writeln!(
            s,
            "| {} | {:.2} px | {:.3} px | {:.2} px | {:.3} px | {} / {} |",
            r.model, q[0], q[1], q[2], q[3], q[4], q[5]
        )?;
    }
    writeln!(
        s,
        "\n### The other DoIs ({STEPS} steps, default thresholds, balanced)\n"
    )?;
    writeln!(
        s,
        "Haptic (§4.2): per face, the Clough-Tocher G¹ error (eq. (5) solved exactly, its out-of-plane \
         residual counted, eq. (6)) over 12 τ and the depth by which the face's patch crosses the face's plane \
         over τ L, the larger of the two against 1, with τ = {} and L the cage's mean edge length (the paper gives \
         no value). Haptic point: the bbox point min + (0.9, 0.6, 0.5) × extent snapped to the closest surface \
         point. Curvature: the vertex DoI (largest angle between the vertex normal and its faces' normals, \
         t = 15°), vertex values to faces by max / avg / min.\n",
        Haptic::DEFAULT_TOLERANCE
    )?;
    writeln!(
        s,
        "| model | uniform | haptic | haptic point | curvature max | curvature avg | curvature min |"
    )?;
    writeln!(s, "|---|---:|---:|---:|---:|---:|---:|")?;
    for r in &rows {
        let u = r.uniform as u64;
        let c = |k: usize| {
            format!(
                "{} ({})",
                thousands(r.others[k] as u64),
                pct(r.others[k] as u64, u)
            )
        };
        writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} |",
            r.model,
            thousands(u),
            c(0),
            c(1),
            c(2),
            c(3),
            c(4)
        )?;
    }
    writeln!(s, "\n### Smallest triangle angle after 5 steps\n")?;
    writeln!(
        s,
        "Plain closure → balanced (the default: level balancing, two split edges refined red, no green \
         bisection below the input's smallest angle unless it is an exact bisection of a fat triangle, one \
         pass per level reading every vertex at that level, so vertices sit at their uniform Loop positions; \
         `subdiv_loop::loop_step`). The classic red-green bound asks for at least half the input's smallest \
         angle. The teapot's lip is a ring of strips holding the input's smallest angle (uniform Loop: 2.72° \
         at every level 1 to 5): a green bisection of a strip's short edge halves its angle, and smoothing \
         vertices over rings that mix levels moves them by about a strip's width; the plain closure does both.\n"
    )?;
    let names: Vec<&str> = rows[0].quality.1.iter().map(|q| q.0).collect();
    writeln!(s, "| model | input (bound) | {} |", names.join(" | "))?;
    writeln!(s, "|---|---:|{}", "---:|".repeat(names.len()))?;
    for r in &rows {
        let (input, q) = &r.quality;
        let cells: Vec<String> = q
            .iter()
            .map(|(_, [p, b], _)| format!("{p:.2}° → {b:.2}°"))
            .collect();
        writeln!(
            s,
            "| {} | {input:.2}° ({:.2}°) | {} |",
            r.model,
            input * 0.5,
            cells.join(" | ")
        )?;
    }
    writeln!(
        s,
        "\nTriangles after the same 5 steps, plain closure → balanced (the cost of the quality bound):\n"
    )?;
    writeln!(s, "| model | {} |", names.join(" | "))?;
    writeln!(s, "|---|{}", "---:|".repeat(names.len()))?;
    for r in &rows {
        let cells: Vec<String> = r
            .quality
            .1
            .iter()
            .map(|(_, _, [p, b])| {
                let cost = 100.0 * (*b as f64 / *p as f64 - 1.0);
                format!(
                    "{} → {} ({cost:+.0} %)",
                    thousands(*p as u64),
                    thousands(*b as u64)
                )
            })
            .collect();
        writeln!(s, "| {} | {} |", r.model, cells.join(" | "))?;
    }
    crate::figures_focus::section(root, &mut s)?;
    writeln!(s, "{END}")?;

    let path = root.join("docs/figures.md");
    let old = std::fs::read_to_string(&path).unwrap_or_else(|_| "# Figures\n\nReproductions of the papers' figures and tables, generated by `cargo xtask figures`.\n".to_string());
    let new = match (old.find(BEGIN), old.find(END)) {
        (Some(b), Some(e)) if e > b => {
            format!("{}{}{}", &old[..b], s.trim_end(), &old[e + END.len()..])
        }
        _ => format!("{}\n{}", old.trim_end().to_string() + "\n", s),
    };
    std::fs::write(&path, new).with_context(|| format!("writing {}", path.display()))?;
    println!(
        "figures (DoI): wrote {} in {:.1} s",
        path.display(),
        t0.elapsed().as_secs_f64()
    );
    print!("{s}");
    Ok(())
}
