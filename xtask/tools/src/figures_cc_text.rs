//! The Catmull-Clark section of `docs/figures.md` (Settgast et al. 2004, Figs. 5–7), generated
//! from `docs/figures/cc_run.csv`, `fig5_triangles.csv`, `fig6_quads.csv`, `fig7_framerate.csv`
//! and `fig57_error.csv` only: every number it states is computed here from those files, and
//! `figures_check.rs` regenerates the section and recomputes its claims independently.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Result, bail};

use crate::figures_table::Table;

/// The section's markers in `docs/figures.md`.
pub const BEGIN: &str = "<!-- figures:cc:begin -->";
/// End marker of the section.
pub const END: &str = "<!-- figures:cc:end -->";

/// A frame "holds" the target when its rate is within this fraction of it (±10 %).
pub const BAND: f64 = 0.10;

/// The Catmull-Clark figures' data: one table per CSV file.
pub struct CcData {
    /// `cc_run.csv`: `key,value` rows: the run's settings and duration.
    pub run: Table,
    /// `fig5_triangles.csv`: `frame,adaptive,uniform2,uniform3,uniform4`.
    pub triangles: Table,
    /// `fig6_quads.csv`: `frame,depth0,..`: adaptive quads per depth.
    pub quads: Table,
    /// `fig7_framerate.csv`: [`FRAMERATE_COLUMNS`]: the rendered runs' rates per frame; the
    /// paper's scenario under the predictive (`budget`) and the paper's controller (`paper`;
    /// maxsd, share: its state in each frame), the predictive one's predicted frame time; the
    /// predictive controller held at uniform depth 2's and 3's rates (`held2`, `held3`).
    pub framerate: Table,
    /// `fig57_error.csv`: `frame,config,silhouette_px_max,silhouette_px_p99,shading_deg_p99`,
    /// config one of `adaptive`, `uniform2..4` (Figs. 5 and 6 runs), `budget`, `paper`, `held2`,
    /// `held3` (Fig. 7 runs).
    pub error: Table,
}

/// The columns of `fig7_framerate.csv`.
pub const FRAMERATE_COLUMNS: [&str; 17] = [
    "frame",
    "uniform2",
    "uniform3",
    "uniform4",
    "adaptive",
    "budget",
    "paper",
    "target",
    "budget_predicted_ms",
    "budget_triangles",
    "paper_triangles",
    "paper_maxsd",
    "paper_share",
    "held2",
    "held3",
    "held2_triangles",
    "held3_triangles",
];

/// The CSV files of [`CcData`], in field order.
pub const FILES: [&str; 5] = [
    "cc_run.csv",
    "fig5_triangles.csv",
    "fig6_quads.csv",
    "fig7_framerate.csv",
    "fig57_error.csv",
];

impl CcData {
    /// Writes the tables into `dir`.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let t = [
            &self.run,
            &self.triangles,
            &self.quads,
            &self.framerate,
            &self.error,
        ];
        for (t, f) in t.iter().zip(FILES) {
            t.write(&dir.join(f))?;
        }
        Ok(())
    }

    /// Reads the tables from `dir`.
    pub fn read(dir: &Path) -> Result<CcData> {
        let t = |i: usize| Table::read(&dir.join(FILES[i]));
        Ok(CcData {
            run: t(0)?,
            triangles: t(1)?,
            quads: t(2)?,
            framerate: t(3)?,
            error: t(4)?,
        })
    }

    /// A setting of `cc_run.csv`.
    pub fn setting(&self, key: &str) -> Result<f64> {
        self.run.number("key", key, "value")
    }
}

/// Mean of `v` (0 for none).
pub fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// Median of `v` (upper median; 0 for none).
pub fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

fn min(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Image error of one configuration over its measured frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSummary {
    /// Measured frames.
    pub frames: usize,
    /// Largest per-frame silhouette maximum (px).
    pub silhouette_worst: f64,
    /// Median over frames of the per-frame silhouette maximum (px).
    pub silhouette_median: f64,
    /// Median over frames of the per-frame shading 99th percentile (degrees).
    pub shading_median: f64,
}

/// The error rows of `config`, restricted to frames in `range`.
pub fn error_summary(
    error: &Table,
    config: &str,
    range: std::ops::Range<usize>,
) -> Result<ErrorSummary> {
    let t = error.filter("config", config)?;
    let frames = t.f64s("frame")?;
    let pick = |col: &str| -> Result<Vec<f64>> {
        Ok(t.f64s(col)?
            .into_iter()
            .zip(&frames)
            .filter(|(_, f)| range.contains(&(**f as usize)))
            .map(|(x, _)| x)
            .collect())
    };
    let (sil, shade) = (pick("silhouette_px_max")?, pick("shading_deg_p99")?);
    if sil.is_empty() {
        bail!("no image error of {config} in frames {range:?}");
    }
    Ok(ErrorSummary {
        frames: sil.len(),
        silhouette_worst: max(&sil),
        silhouette_median: median(&sil),
        shading_median: median(&shade),
    })
}

/// What the text says of the load the figures were measured under.
pub fn load_note(d: &CcData) -> Result<String> {
    let (start, end, max) = (
        d.setting("load_start")?,
        d.setting("load_end")?,
        d.setting("max_load")?,
    );
    Ok(if d.setting("forced")? > 0.0 {
        format!(
            "**Measured on a loaded machine, forced** (`--force`): the 1-minute load average was \
             {start:.2} at the start, above the {max} the figures are refused at, and {end:.2} at \
             the end; the frame rates show the other work too."
        )
    } else {
        format!(
            "Measured on an idle machine: 1-minute load average {start:.2} at the start (the figures \
             are refused above {max}) and {end:.2} at the end."
        )
    })
}

/// The uniform depths of the figures.
pub const UNIFORM: [u32; 3] = [2, 3, 4];

/// The Catmull-Clark section (markers included), from the tables only.
pub fn markdown(d: &CcData) -> Result<String> {
    let mut s = String::new();
    writeln!(s, "{BEGIN}")?;
    writeln!(
        s,
        "## Adaptive Catmull-Clark tessellation (Settgast et al. 2004, Figs. 5–7)\n"
    )?;
    let set = |k: &str| d.setting(k);
    writeln!(
        s,
        "Generated by `cargo xtask figures` (this part: {:.0} s; `xtask/tools/src/figures_cc.rs`) from `subdiv bench framerate` \
         runs; the data are `docs/figures/cc_run.csv`, `fig5_triangles.csv`, `fig57_error.csv`, `fig6_quads.csv` and \
         `fig7_framerate.csv`, and this text is computed from them (`xtask/tools/src/figures_cc_text.rs`; the test in \
         `xtask/tools/src/figures_check.rs` regenerates it and fails on any difference). Scene: 40 instances of \
         `catmark_helmet`, {:.0} cage faces, camera orbiting the scene centre {}° per frame, {:.0}×{:.0} pixels, \
         adaptive depths 0–{:.0} (`DepthParams` defaults: curvature, classification, projected size). {}\n",
        set("seconds")?,
        set("faces")?,
        set("orbit_step_deg")?,
        set("width")?,
        set("height")?,
        set("max_depth")?,
        load_note(d)?,
    )?;
    writeln!(
        s,
        "**Image error** (`subdiv bench framerate --error-every {k:.0} --error-size {ew:.0}x{eh:.0}`): every {k:.0}th \
         frame is also rendered at {ew:.0}×{eh:.0} (3×3 samples per pixel) and compared with uniform depth {r:.0} \
         seen from the same camera (the true surface; `subdiv_quality`, as `subdiv bench quality`): silhouette \
         error = for each pixel where the coverage masks disagree, its distance in pixels to the reference \
         silhouette (per frame: the largest); shading error = the 99th percentile of the angle between the \
         normals inside both masks. The error renders are not part of the frame times.\n",
        k = set("error_every")?,
        ew = set("error_width")?,
        eh = set("error_height")?,
        r = set("reference_depth")?,
    )?;
    fig5(d, &mut s)?;
    fig6(d, &mut s)?;
    crate::figures_cc_fig7::fig7(d, &mut s)?;
    writeln!(s, "{END}")?;
    Ok(s)
}

fn fig5(d: &CcData, s: &mut String) -> Result<()> {
    let tri = d.triangles.f64s("adaptive")?;
    let u: Vec<f64> = UNIFORM
        .iter()
        .map(|k| d.triangles.f64s(&format!("uniform{k}")).map(|v| mean(&v)))
        .collect::<Result<_>>()?;
    writeln!(s, "![Fig. 5](figures/fig5_triangles.png)\n")?;
    writeln!(
        s,
        "**Fig. 5** Triangles per frame over {} frames: adaptive {:.0} on average (min {:.0}, max {:.0}) against \
         uniform depth 2: {:.0}, 3: {:.0}, 4: {:.0} (the uniform counts include the back faces). The adaptive count \
         is {:.1} % of uniform depth 4 and {:.1} % of uniform depth 3.\n",
        tri.len(),
        mean(&tri),
        min(&tri),
        max(&tri),
        u[0],
        u[1],
        u[2],
        100.0 * mean(&tri) / u[2],
        100.0 * mean(&tri) / u[1],
    )?;
    writeln!(s, "![Fig. 5, image error](figures/fig5_error.png)\n")?;
    let n = d.triangles.rows.len();
    let ada = error_summary(&d.error, "adaptive", 0..n)?;
    writeln!(
        s,
        "**Fig. 5, image error** per measured frame ({} frames; the plot shows the shading error per frame, the \
         table both errors), against uniform depth {:.0}:\n",
        ada.frames,
        d.setting("reference_depth")?
    )?;
    writeln!(
        s,
        "| tessellation | triangles (mean) | silhouette px, worst frame | silhouette px, median frame | shading ° p99, median frame |"
    )?;
    writeln!(s, "|---|---:|---:|---:|---:|")?;
    let row = |s: &mut String, name: &str, tris: f64, e: &ErrorSummary| {
        writeln!(
            s,
            "| {name} | {tris:.0} | {:.2} | {:.2} | {:.2} |",
            e.silhouette_worst, e.silhouette_median, e.shading_median
        )
    };
    row(s, "adaptive", mean(&tri), &ada)?;
    let mut no_worse = None;
    for (k, &depth) in UNIFORM.iter().enumerate() {
        let e = error_summary(&d.error, &format!("uniform{depth}"), 0..n)?;
        row(s, &format!("uniform depth {depth}"), u[k], &e)?;
        if no_worse.is_none()
            && e.silhouette_worst <= ada.silhouette_worst
            && e.shading_median <= ada.shading_median
        {
            no_worse = Some((depth, u[k]));
        }
    }
    writeln!(s)?;
    match no_worse {
        Some((depth, t)) => writeln!(
            s,
            "The least uniform depth whose worst-frame silhouette error and median shading error are both no worse \
             than adaptive's is depth {depth}, with {:.2} times adaptive's triangles.\n",
            t / mean(&tri)
        )?,
        None => writeln!(
            s,
            "No uniform depth up to {} has both a worst-frame silhouette error and a median shading error no worse \
             than adaptive's.\n",
            UNIFORM[UNIFORM.len() - 1]
        )?,
    }
    Ok(())
}

fn fig6(d: &CcData, s: &mut String) -> Result<()> {
    let depths: Vec<String> = d
        .quads
        .header
        .iter()
        .filter(|h| h.starts_with("depth"))
        .cloned()
        .collect();
    let avg: Vec<f64> = depths
        .iter()
        .map(|h| d.quads.f64s(h).map(|v| mean(&v)))
        .collect::<Result<_>>()?;
    let total: f64 = avg.iter().sum();
    let parts: Vec<String> = depths
        .iter()
        .zip(&avg)
        .map(|(h, a)| {
            format!(
                "{}: {a:.0} ({:.1} %)",
                h.replace("depth", "depth "),
                100.0 * a / total
            )
        })
        .collect();
    writeln!(s, "![Fig. 6](figures/fig6_quads.png)\n")?;
    writeln!(
        s,
        "**Fig. 6** Quads per depth per frame, before gap prevention (as the paper counts them: a patch at \
         depth d is 4^d quads), adaptive: on average {} of {total:.0} quads per frame.\n",
        parts.join(", ")
    )?;
    Ok(())
}

/// How many of `fps` lie within [`BAND`] of the median of all: the noise of a fixed workload,
/// the ceiling of any controller's hold.
pub fn own_band(fps: &[f64]) -> usize {
    let m = median(fps);
    fps.iter().filter(|&&f| (f / m - 1.0).abs() <= BAND).count()
}

/// The frame ranges of the controlled runs' two phases (before and after the switch).
pub fn phases(d: &CcData) -> Result<[std::ops::Range<usize>; 2]> {
    let n = d.framerate.rows.len();
    let switch = d.setting("switch_frame")? as usize;
    if switch == 0 || switch >= n {
        bail!("switch frame {switch} outside 1..{n}");
    }
    Ok([0..switch, switch..n])
}
