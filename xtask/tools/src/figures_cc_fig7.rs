//! The Fig. 7 part of the Catmull-Clark section of `docs/figures.md`: frame rates of the fixed
//! workloads, the paper's scenario (14–15 then 39–40 fps) under the predictive and the paper's
//! controller side by side, and the predictive controller held at uniform depths' rates with
//! its picture measured against the next depth (a level of quality for free). Computed from the
//! tables only, like the rest of the section (`figures_cc_text.rs`); `figures_check.rs`
//! recomputes the claims independently.

use std::fmt::Write as _;
use std::ops::Range;

use anyhow::Result;

use crate::figures_cc_text::{
    BAND, CcData, ErrorSummary, UNIFORM, error_summary, mean, median, own_band, phases,
};

/// How one phase of a controlled run meets its target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phase {
    /// Frames of the phase within [`BAND`] of the target.
    pub within: usize,
    /// Frames of the phase.
    pub frames: usize,
    /// The first frame of the phase within the band, counted from the phase's start.
    pub first: Option<usize>,
    /// The share of the frames from that first one to the phase's end within the band.
    pub share_after: f64,
    /// Median rate over the second half of the phase.
    pub late_median: f64,
}

/// [`Phase`] of frames `range` of `fps` against `target`.
pub fn phase(fps: &[f64], range: Range<usize>, target: f64) -> Phase {
    let near = |i: usize| (fps[i] / target - 1.0).abs() <= BAND;
    let first = range.clone().find(|&i| near(i));
    let share_after = first.map_or(0.0, |f| {
        (f..range.end).filter(|&i| near(i)).count() as f64 / (range.end - f) as f64
    });
    let mid = range.start + range.len() / 2;
    Phase {
        within: range.clone().filter(|&i| near(i)).count(),
        frames: range.len(),
        first: first.map(|f| f - range.start),
        share_after,
        late_median: median(&fps[mid..range.end]),
    }
}

/// The median over frames 1.. of `|predicted - measured| / measured`, in percent.
pub fn prediction_error(fps: &[f64], predicted_ms: &[f64]) -> f64 {
    let e: Vec<f64> = fps
        .iter()
        .zip(predicted_ms)
        .skip(1)
        .map(|(f, p)| (p * f / 1e3 - 1.0).abs() * 100.0)
        .collect();
    median(&e)
}

/// `no worse` when both of `a`'s errors are at most `b`'s, else `worse`.
pub fn verdict(a: &ErrorSummary, b: &ErrorSummary) -> &'static str {
    if a.silhouette_worst <= b.silhouette_worst && a.shading_median <= b.shading_median {
        "no worse"
    } else {
        "worse"
    }
}

/// The Fig. 7 part.
pub fn fig7(d: &CcData, s: &mut String) -> Result<()> {
    let fr = &d.framerate;
    let n = fr.rows.len();
    let med = |col: &str| -> Result<f64> { Ok(median(&fr.f64s(col)?[1..])) };
    let f: Vec<f64> = UNIFORM
        .iter()
        .map(|k| med(&format!("uniform{k}")))
        .collect::<Result<_>>()?;
    let fa = med("adaptive")?;
    let u2_within = own_band(&fr.f64s("uniform2")?[1..]);
    let ceiling = u2_within as f64 / (n - 1) as f64;
    writeln!(s, "![Fig. 7](figures/fig7_framerate.png)\n")?;
    writeln!(
        s,
        "**Fig. 7** Frames per second on lavapipe (CPU Vulkan; tessellation, upload and rendering at {:.0} \
         sample per pixel, as the paper's renderer drew; {n} frames each): medians over frames 1–{} of uniform \
         depth 2: {:.1}, 3: {:.1}, 4: {:.1} fps (paper, GeForce 4: \
         31, 17, 7) and adaptive without control: {fa:.1} fps. Uniform depth 2, a fixed workload, has {u2_within} \
         of its {} frames within ±10 % of their median: a share of {ceiling:.3}, the ceiling of any \
         controller's hold on this machine.\n",
        d.setting("samples")?,
        n - 1,
        f[0],
        f[1],
        f[2],
        n - 1,
    )?;
    let targets = fr.f64s("target")?;
    let ph = phases(d)?;
    let (t1, t2) = (targets[ph[0].start], targets[ph[1].start]);
    writeln!(
        s,
        "**The paper's scenario** (`--target-fps {t1:.2} --switch-fps {t2:.2}`: {t1:.1} fps for frames 0–{}, \
         then {t2:.1} fps; the paper: \"from a given frame rate of 14 – 15 fps to 39 – 40 fps within 70 \
         frames\") under the predictive controller (`--control budget`, the default: each frame, the depths \
         with the least estimated image error whose frame time, as a model fitted to the machine predicts it, \
         fits the budget) and under the paper's (`--control paper`: `maxsd` first, then a share of the patches \
         one level, by feedback):\n",
        ph[1].start - 1
    )?;
    writeln!(
        s,
        "| controller | target fps | frames within ±10 % | first within ±10 %, frames into the phase | share within ±10 % from there | median fps, second half |"
    )?;
    writeln!(s, "|---|---:|---:|---:|---:|---:|")?;
    let mut at = Vec::new();
    for (col, name) in [("budget", "predictive"), ("paper", "paper")] {
        let fps = fr.f64s(col)?;
        for (range, t) in ph.iter().zip([t1, t2]) {
            let p = phase(&fps, range.clone(), t);
            let first = p
                .first
                .map_or_else(|| "never".to_string(), |k| k.to_string());
            writeln!(
                s,
                "| {name} | {t:.1} | {} of {} | {first} | {:.3} | {:.1} |",
                p.within, p.frames, p.share_after, p.late_median
            )?;
            at.push(p);
        }
    }
    let (b2, p2) = (at[1], at[3]);
    let frames = |p: &Phase| p.first.map_or_else(|| "no".to_string(), |k| k.to_string());
    let err = prediction_error(&fr.f64s("budget")?, &fr.f64s("budget_predicted_ms")?);
    writeln!(
        s,
        "\nAfter the switch the predictive controller's first frame within ±10 % of the new target comes {} \
         frames after it (the target: at most 10; the paper: 70), the paper's controller's {}. From that \
         frame on, a share of {:.3} of the predictive controller's frames at the second target is within the \
         band, {:.2} times the machine's ceiling (the target: at least 0.9). Its model predicted the frame \
         times to within {err:.1} % (median over frames 1–{} of |predicted − measured| / measured).\n",
        frames(&b2),
        frames(&p2),
        b2.share_after,
        b2.share_after / ceiling.max(f64::MIN_POSITIVE),
        n - 1
    )?;
    held(d, &f, s)?;
    curve_errors(d, &f, fa, &ph, s)
}

/// The predictive controller held at uniform depth 2's and 3's rates, against depths 3 and 4.
fn held(d: &CcData, f: &[f64], s: &mut String) -> Result<()> {
    let fr = &d.framerate;
    let n = fr.rows.len();
    let n5 = d.triangles.rows.len();
    writeln!(
        s,
        "**A level of quality for free**: the predictive controller held at uniform depth 2's rate (`--target-fps \
         {:.2}`) and at uniform depth 3's (`--target-fps {:.2}`), its picture measured as the Fig. 5 runs are, \
         against the next uniform depth's (the same cameras; the target: no worse):\n",
        d.setting("held2_target")?,
        d.setting("held3_target")?,
    )?;
    writeln!(
        s,
        "| run | fps (median) | triangles (mean) | silhouette px, worst frame | shading ° p99, median frame |"
    )?;
    writeln!(s, "|---|---:|---:|---:|---:|")?;
    let mut verdicts = Vec::new();
    for (k, depth) in [(2usize, 3usize), (3, 4)] {
        let held = error_summary(&d.error, &format!("held{k}"), 0..n)?;
        let next = error_summary(&d.error, &format!("uniform{depth}"), 0..n5)?;
        writeln!(
            s,
            "| predictive at uniform depth {k}'s rate | {:.1} | {:.0} | {:.2} | {:.2} |",
            median(&fr.f64s(&format!("held{k}"))?[1..]),
            mean(&fr.f64s(&format!("held{k}_triangles"))?),
            held.silhouette_worst,
            held.shading_median
        )?;
        writeln!(
            s,
            "| uniform depth {depth} | {:.1} | {:.0} | {:.2} | {:.2} |",
            f[depth - 2],
            mean(&d.triangles.f64s(&format!("uniform{depth}"))?),
            next.silhouette_worst,
            next.shading_median
        )?;
        verdicts.push((k, depth, verdict(&held, &next), held, next));
    }
    writeln!(s)?;
    for (k, depth, v, h, u) in verdicts {
        writeln!(
            s,
            "- At uniform depth {k}'s rate the predictive picture is {v} than uniform depth {depth}'s: silhouette \
             {:.2} against {:.2} px, shading {:.2}° against {:.2}°.",
            h.silhouette_worst, u.silhouette_worst, h.shading_median, u.shading_median
        )?;
    }
    writeln!(s)?;
    Ok(())
}

/// The image error of each curve of Fig. 7.
fn curve_errors(
    d: &CcData,
    f: &[f64],
    fa: f64,
    ph: &[Range<usize>; 2],
    s: &mut String,
) -> Result<()> {
    let n5 = d.triangles.rows.len();
    writeln!(
        s,
        "Image error of each curve (measured frames; the uniform depths and adaptive without control from the \
         Fig. 5 runs, whose cameras are the same):\n"
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
    let targets = d.framerate.f64s("target")?;
    for (col, name) in [("budget", "predictive"), ("paper", "paper's")] {
        let fps = d.framerate.f64s(col)?;
        let tris = d.framerate.f64s(&format!("{col}_triangles"))?;
        for (k, r) in ph.iter().enumerate() {
            let e = error_summary(&d.error, col, r.clone())?;
            writeln!(
                s,
                "| {name} control, target {:.1} fps ({} phase) | {:.1} | {:.0} | {:.2} | {:.2} |",
                targets[r.start],
                ["first", "second"][k],
                median(&fps[r.start.max(1)..r.end]),
                mean(&tris[r.clone()]),
                e.silhouette_worst,
                e.shading_median
            )?;
        }
    }
    writeln!(s)?;
    Ok(())
}
