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
    /// `fig7_framerate.csv`: `frame,uniform2,uniform3,uniform4,adaptive,controlled,target,
    /// maxsd,share,controlled_triangles` (maxsd, share: the controller's state in each frame).
    pub framerate: Table,
    /// `fig57_error.csv`: `frame,config,silhouette_px_max,silhouette_px_p99,shading_deg_p99`,
    /// config one of `adaptive`, `uniform2..4`, `controlled`.
    pub error: Table,
}

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

/// Frames of the running median the controller decides on (`subdiv_depth`'s `WINDOW`).
pub const RUNNING: usize = 5;

/// The running median of `fps` at frame `i`: the median of frames `i-4..=i` (fewer at the
/// run's start; for an even count the mean of the middle two).
pub fn running_median(fps: &[f64], i: usize) -> f64 {
    median(&fps[(i + 1).saturating_sub(RUNNING)..=i])
}

/// How a phase of the controlled run meets its target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hold {
    /// Frames of the phase within [`BAND`] of the target.
    pub within: usize,
    /// Frames of the phase whose [`running_median`] is within [`BAND`] of the target.
    pub running_within: usize,
    /// The first frame (absolute) from which every frame's running median to the phase's end
    /// is within the band; `None` when the last one is outside it.
    pub running_settled_from: Option<usize>,
    /// Frames of the phase.
    pub frames: usize,
    /// The first frame (absolute) from which every frame to the phase's end is within the band;
    /// `None` when the phase's last frame is outside it.
    pub settled_from: Option<usize>,
    /// Median rate over the second half of the phase.
    pub late_median: f64,
}

/// [`Hold`] of frames `range` of `fps` against `target`.
pub fn hold(fps: &[f64], range: std::ops::Range<usize>, target: f64) -> Hold {
    let near = |f: f64| (f / target - 1.0).abs() <= BAND;
    let ok = |i: usize| near(fps[i]);
    let running_ok = |i: usize| near(running_median(fps, i));
    let settled = |ok: &dyn Fn(usize) -> bool| {
        let mut from = None;
        for i in range.clone().rev() {
            if !ok(i) {
                break;
            }
            from = Some(i);
        }
        from
    };
    let settled_from = settled(&ok);
    let mid = range.start + range.len() / 2;
    Hold {
        within: range.clone().filter(|&i| ok(i)).count(),
        running_within: range.clone().filter(|&i| running_ok(i)).count(),
        running_settled_from: settled(&running_ok),
        frames: range.len(),
        settled_from,
        late_median: median(&fps[mid..range.end]),
    }
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
         adaptive depths 0–{:.0} (`DepthParams` defaults: curvature, classification, projected size).\n",
        set("seconds")?,
        set("faces")?,
        set("orbit_step_deg")?,
        set("width")?,
        set("height")?,
        set("max_depth")?,
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
    fig7(d, &mut s)?;
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

/// How many of `fps`, and how many of their [`running_median`]s, lie within [`BAND`] of the
/// median of all: the noise of a fixed workload, the ceiling of any controller's hold.
pub fn own_band(fps: &[f64]) -> (usize, usize) {
    let m = median(fps);
    let near = |f: f64| (f / m - 1.0).abs() <= BAND;
    (
        fps.iter().filter(|&&f| near(f)).count(),
        (0..fps.len())
            .filter(|&i| near(running_median(fps, i)))
            .count(),
    )
}

/// The frame ranges of the controlled run's two phases.
pub fn phases(d: &CcData) -> Result<[std::ops::Range<usize>; 2]> {
    let n = d.framerate.rows.len();
    let switch = d.setting("switch_frame")? as usize;
    if switch == 0 || switch >= n {
        bail!("switch frame {switch} outside 1..{n}");
    }
    Ok([0..switch, switch..n])
}

fn fig7(d: &CcData, s: &mut String) -> Result<()> {
    let fr = &d.framerate;
    let n = fr.rows.len();
    let med = |col: &str| -> Result<f64> { Ok(median(&fr.f64s(col)?[1..])) };
    let f: Vec<f64> = UNIFORM
        .iter()
        .map(|k| med(&format!("uniform{k}")))
        .collect::<Result<_>>()?;
    let fa = med("adaptive")?;
    let targets = fr.f64s("target")?;
    let fps = fr.f64s("controlled")?;
    let ph = phases(d)?;
    let (t1, t2) = (targets[ph[0].start], targets[ph[1].start]);
    let u2_band = own_band(&fr.f64s("uniform2")?[1..]);
    writeln!(s, "![Fig. 7](figures/fig7_framerate.png)\n")?;
    writeln!(
        s,
        "**Fig. 7** Frames per second on lavapipe (CPU Vulkan; tessellation + rendering, {n} frames each; the machine \
         has 2 cores shared with other work, 1-minute load average {:.1} when this part started and {:.1} when it \
         ended, so single frames are noisy: of uniform depth 2's {} frames, a fixed workload, only {} lie within \
         ±10 % of their median, and the median of the last {RUNNING} frames in {}: the ceiling of any controller's \
         hold): medians over frames 1–{} of uniform depth 2: {:.1}, 3: {:.1}, 4: {:.1} fps (paper, GeForce 4: 31, \
         17, 7) and adaptive without control: {fa:.1} fps. Adaptive with frame-rate control (`--target-fps {t1:.2} \
         --switch-fps {t2:.2}`: `maxsd` first, then a share of the patches one level by priority, back faces never \
         raised; deciding on the median of the last {RUNNING} frame times since its last change, steps weighted by \
         the error's signal-to-noise ratio, holding while that median stays within ±10 %): target {t1:.1} fps \
         ({:.2} times uniform depth 2's rate; the paper: 39–40 against 31) for frames 0–{}, then {t2:.1} fps. The \
         controller can only meet the rate of the median of {RUNNING} frames, not of each frame: both are counted.\n",
        d.setting("load_start")?,
        d.setting("load_end")?,
        n - 1,
        u2_band.0,
        u2_band.1,
        n - 1,
        f[0],
        f[1],
        f[2],
        t1 / f[0],
        ph[1].start - 1,
    )?;
    let (cap, share) = (fr.f64s("maxsd")?, fr.f64s("share")?);
    let max_depth = d.setting("max_depth")?;
    for (k, (range, t)) in ph.iter().zip([t1, t2]).enumerate() {
        let h = hold(&fps, range.clone(), t);
        let most = range
            .clone()
            .filter(|&i| cap[i] == max_depth && share[i] > 0.0)
            .count();
        let least = range.clone().filter(|&i| cap[i] == 0.0).count();
        let settled = match h.settled_from {
            Some(i) => format!(
                "every frame from frame {i} on ({} frames after the phase began) is within ±10 %{}",
                i - range.start,
                if i + 1 == range.end {
                    " (that is, only the phase's last frame)"
                } else {
                    ""
                }
            ),
            None => format!(
                "the phase's last frame (frame {}) is outside ±10 %, so no frame from which every frame \
                 stays within it",
                range.end - 1
            ),
        };
        let running = match h.running_settled_from {
            Some(i) => format!(
                "in every frame since frame {i} ({} frames after the phase began)",
                i - range.start
            ),
            None => "not in the phase's last frame".to_string(),
        };
        writeln!(
            s,
            "- {} target, {t:.1} fps (frames {}–{}): {} of {} frames within ±10 %; {settled}. The median of the \
             last {RUNNING} frames is within ±10 % in {} of {} frames, {running}. Median of the phase's second \
             half {:.1} fps; the controller was at maxsd {max_depth} raising patches above their geometric depths in \
             {most} frames and at maxsd 0 (every patch at depth 0) in {least}.",
            ["First", "Second"][k],
            range.start,
            range.end - 1,
            h.within,
            h.frames,
            h.running_within,
            h.frames,
            h.late_median
        )?;
    }
    writeln!(s)?;
    fig7_errors(d, &f, fa, &ph, s)
}

fn fig7_errors(
    d: &CcData,
    f: &[f64],
    fa: f64,
    ph: &[std::ops::Range<usize>; 2],
    s: &mut String,
) -> Result<()> {
    let n5 = d.triangles.rows.len();
    writeln!(
        s,
        "Image error of each curve (measured frames; the uniform depths and adaptive without control from the Fig. 5 runs, whose \
         cameras are the same):\n"
    )?;
    writeln!(
        s,
        "| curve | fps (median) | triangles (mean) | silhouette px, worst frame | shading ° p99, median frame |"
    )?;
    writeln!(s, "|---|---:|---:|---:|---:|")?;
    for (k, depth) in UNIFORM.iter().enumerate() {
        let e = error_summary(&d.error, &format!("uniform{depth}"), 0..n5)?;
        let t = mean(&d.triangles.f64s(&format!("uniform{depth}"))?);
        writeln!(
            s,
            "| uniform depth {depth} | {:.1} | {t:.0} | {:.2} | {:.2} |",
            f[k], e.silhouette_worst, e.shading_median
        )?;
    }
    let e = error_summary(&d.error, "adaptive", 0..n5)?;
    writeln!(
        s,
        "| adaptive, no control | {fa:.1} | {:.0} | {:.2} | {:.2} |",
        mean(&d.triangles.f64s("adaptive")?),
        e.silhouette_worst,
        e.shading_median
    )?;
    let fps = d.framerate.f64s("controlled")?;
    let tris = d.framerate.f64s("controlled_triangles")?;
    let targets = d.framerate.f64s("target")?;
    let mut phase_err = Vec::new();
    for (k, r) in ph.iter().enumerate() {
        let e = error_summary(&d.error, "controlled", r.clone())?;
        writeln!(
            s,
            "| adaptive, target {:.1} fps ({} phase) | {:.1} | {:.0} | {:.2} | {:.2} |",
            targets[r.start],
            ["first", "second"][k],
            median(&fps[r.start.max(1)..r.end]),
            mean(&tris[r.clone()]),
            e.silhouette_worst,
            e.shading_median
        )?;
        phase_err.push(e);
    }
    let late = hold(&fps, ph[0].clone(), targets[ph[0].start]).late_median;
    let u2 = error_summary(&d.error, "uniform2", 0..n5)?;
    writeln!(
        s,
        "\nAt the first target the controlled rate (median of the phase's second half) is {:.1} fps, {} uniform \
         depth 2's {:.1} fps; its worst-frame silhouette error is {:.2} px against uniform depth 2's {:.2} px, its \
         median shading error {:.2}° against {:.2}°.\n",
        late,
        if late > f[0] { "above" } else { "not above" },
        f[0],
        phase_err[0].silhouette_worst,
        u2.silhouette_worst,
        phase_err[0].shading_median,
        u2.shading_median
    )?;
    Ok(())
}
