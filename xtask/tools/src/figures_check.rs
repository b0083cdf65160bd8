//! The test that keeps `docs/figures.md` honest (run by `cargo xtask test` through
//! `cargo test --workspace`): both generated sections must equal what their generators make of
//! the CSV files in `docs/figures/` (so every number stated is recomputed from the data), and the
//! claims that matter most are recomputed a second time, independently of the generator, from
//! the CSV files: the frames within ±10 % of each target and the frame from which every frame
//! stays within, the average triangle count, and the comparisons of rates and errors.

use std::path::PathBuf;

use anyhow::{Context, Result, ensure};

use crate::figures_cc_text::{self as cc, CcData};
use crate::figures_doi_text::{self as doi, DoiData};

/// The part of `doc` from `begin` to `end`, markers included.
pub fn section<'a>(doc: &'a str, begin: &str, end: &str) -> Option<&'a str> {
    let b = doc.find(begin)?;
    let e = doc[b..].find(end)? + b;
    Some(&doc[b..e + end.len()])
}

fn root() -> PathBuf {
    xtask::root()
}

/// The first line where `want` (generated) and `got` (the document) differ, as an error.
fn same_text(what: &str, want: &str, got: &str) -> Result<()> {
    for (i, (w, g)) in want.lines().zip(got.lines()).enumerate() {
        ensure!(
            w == g,
            "{what}, line {} of the section: docs/figures.md says\n  {g}\nbut the CSV files give\n  {w}\n\
             (regenerate with `cargo xtask figures text`, or rerun `cargo xtask figures`)",
            i + 1
        );
    }
    ensure!(
        want.lines().count() == got.lines().count(),
        "{what}: the section has {} lines, the CSV files give {}",
        got.lines().count(),
        want.lines().count()
    );
    Ok(())
}

/// Both sections of `doc` against the generators' output for the tables.
fn check_doc(doc: &str, cc_data: &CcData, doi_data: &DoiData) -> Result<()> {
    let got = section(doc, doi::BEGIN, doi::END).context("no DoI section in docs/figures.md")?;
    same_text("DoI section", doi::markdown(doi_data)?.trim_end(), got)?;
    let got = section(doc, cc::BEGIN, cc::END).context("no Catmull-Clark section")?;
    same_text(
        "Catmull-Clark section",
        cc::markdown(cc_data)?.trim_end(),
        got,
    )?;
    check_claims(got, cc_data)
}

/// The number right after `key` in `text` (digits, `.`, `-`, `,` as thousands separator).
fn number_after(text: &str, key: &str) -> Result<f64> {
    let at = text
        .find(key)
        .with_context(|| format!("{key:?} not in {text:?}"))?;
    let rest = &text[at + key.len()..];
    let n: String = rest
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == ',')
        .filter(|c| *c != ',')
        .collect();
    let n = n.trim_end_matches('.');
    n.parse()
        .with_context(|| format!("no number after {key:?} in {text:?}"))
}

/// The key claims of the Catmull-Clark section, recomputed here from the CSV files without the
/// generator's helpers.
fn check_claims(text: &str, d: &CcData) -> Result<()> {
    // Fig. 5: the average adaptive triangle count.
    let tri = d.triangles.f64s("adaptive")?;
    let avg = tri.iter().sum::<f64>() / tri.len() as f64;
    let stated = number_after(text, "frames: adaptive ")?;
    ensure!(
        (stated - avg).abs() <= 0.5,
        "Fig. 5 states {stated} triangles on average; the CSV's mean is {avg}"
    );
    // Fig. 7: each phase of the controlled run.
    let fps = d.framerate.f64s("controlled")?;
    let target = d.framerate.f64s("target")?;
    let switch = d.setting("switch_frame")? as usize;
    for (prefix, lo, hi) in [
        ("- First target", 0, switch),
        ("- Second target", switch, fps.len()),
    ] {
        let line = text
            .lines()
            .find(|l| l.starts_with(prefix))
            .with_context(|| format!("no line {prefix:?}"))?;
        let t = target[lo];
        ensure!(
            (number_after(line, "target, ")? - t).abs() < 0.05,
            "{line}: the CSV's target is {t}"
        );
        ensure!(
            number_after(line, "(frames ")? as usize == lo,
            "{line}: starts at {lo}"
        );
        let inside: Vec<bool> = (lo..hi)
            .map(|i| fps[i] >= 0.9 * t && fps[i] <= 1.1 * t)
            .collect();
        let count = inside.iter().filter(|&&x| x).count();
        let stated = number_after(line, "): ")? as usize;
        ensure!(
            stated == count,
            "{line}: {count} frames of {lo}..{hi} lie within 10 % of {t}, not {stated}"
        );
        // The running median of 5 frames (what the controller decides on), recomputed here.
        let running: Vec<bool> = (lo..hi)
            .map(|i| {
                let mut w = fps[(i + 1).saturating_sub(5)..=i].to_vec();
                w.sort_by(f64::total_cmp);
                let m = if w.len() % 2 == 1 {
                    w[w.len() / 2]
                } else {
                    0.5 * (w[w.len() / 2 - 1] + w[w.len() / 2])
                };
                m >= 0.9 * t && m <= 1.1 * t
            })
            .collect();
        let count = running.iter().filter(|&&x| x).count();
        let stated = number_after(line, "frames is within ±10 % in ")? as usize;
        ensure!(
            stated == count,
            "{line}: the running median of {count} frames of {lo}..{hi} lies within 10 % of {t}, not {stated}"
        );
        if line.contains("since frame ") {
            let from = number_after(line, "since frame ")? as usize;
            ensure!(
                from >= lo && from < hi && running[from - lo..].iter().all(|&x| x),
                "{line}: a running median after frame {from} is outside 10 %"
            );
            ensure!(
                from == lo || !running[from - lo - 1],
                "{line}: the running median of frame {} is within 10 % too",
                from - 1
            );
        } else {
            ensure!(
                !running[hi - lo - 1],
                "{line}: says the last running median is outside, the CSV has it within 10 %"
            );
        }
        if line.contains("from frame ") {
            let from = number_after(line, "from frame ")? as usize;
            ensure!(
                from >= lo && from < hi,
                "{line}: frame {from} not in the phase"
            );
            ensure!(
                inside[from - lo..].iter().all(|&x| x),
                "{line}: a frame after {from} is outside 10 %"
            );
            ensure!(
                from == lo || !inside[from - lo - 1],
                "{line}: frame {} is within 10 % too, so the claim should name an earlier frame",
                from - 1
            );
        } else {
            ensure!(
                !inside[hi - lo - 1],
                "{line}: says the last frame is outside, the CSV has it within 10 %"
            );
        }
    }
    // Fig. 7: "above" / "not above" uniform depth 2.
    let mut u2 = d.framerate.f64s("uniform2")?[1..].to_vec();
    u2.sort_by(f64::total_cmp);
    let f2 = u2[u2.len() / 2];
    let mut late = fps[switch / 2..switch].to_vec();
    late.sort_by(f64::total_cmp);
    let late = late[late.len() / 2];
    let above = text.contains(&format!("fps, above uniform depth 2's {f2:.1} fps"));
    let not_above = text.contains(&format!("fps, not above uniform depth 2's {f2:.1} fps"));
    ensure!(
        above != not_above && above == (late > f2),
        "the comparison with uniform depth 2 ({f2:.1} fps) does not match the late rate {late:.1}"
    );
    Ok(())
}

fn data() -> Result<(String, CcData, DoiData)> {
    let doc = std::fs::read_to_string(root().join("docs/figures.md"))?;
    let dir = root().join("docs/figures");
    Ok((doc, CcData::read(&dir)?, DoiData::read(&dir)?))
}

#[test]
fn figures_md_states_what_its_csv_files_show() {
    let (doc, c, d) = data().unwrap();
    if let Err(e) = check_doc(&doc, &c, &d) {
        panic!("{e:#}");
    }
}

#[test]
fn a_changed_number_in_the_text_fails_the_check() {
    let (doc, c, d) = data().unwrap();
    // Every digit of both sections (the first 300 of each), changed one at a time, fails it.
    for (begin, end) in [(doi::BEGIN, doi::END), (cc::BEGIN, cc::END)] {
        let sec = section(&doc, begin, end).unwrap();
        let start = doc.find(begin).unwrap();
        let digits: Vec<usize> = sec
            .char_indices()
            .filter(|(_, ch)| ch.is_ascii_digit())
            .map(|(i, _)| start + i)
            .take(300)
            .collect();
        assert!(digits.len() > 50);
        for at in digits {
            let mut m = doc.clone();
            let to = if m.as_bytes()[at] == b'9' { "8" } else { "9" };
            m.replace_range(at..at + 1, to);
            assert!(
                check_doc(&m, &c, &d).is_err(),
                "digit at byte {at} not checked"
            );
        }
    }
}

#[test]
fn data_that_do_not_hold_the_target_fail_the_claims() {
    let (doc, mut c, _) = data().unwrap();
    let sec = section(&doc, cc::BEGIN, cc::END).unwrap().to_string();
    // Move the last frame of each phase across the band's edge (in if it was out, out if it was
    // in): the stated frame counts and "from frame" claims are no longer what the data show.
    let col = c.framerate.col("controlled").unwrap();
    let tcol = c.framerate.col("target").unwrap();
    let switch = c.setting("switch_frame").unwrap() as usize;
    let n = c.framerate.rows.len();
    for last in [switch - 1, n - 1] {
        let mut m = std::mem::take(&mut c.framerate);
        let t: f64 = m.rows[last][tcol].parse().unwrap();
        let old = m.rows[last][col].clone();
        let was_in = (old.parse::<f64>().unwrap() / t - 1.0).abs() <= cc::BAND;
        m.rows[last][col] = format!("{}", if was_in { t * 1.5 } else { t });
        c.framerate = m;
        assert!(check_claims(&sec, &c).is_err(), "frame {last} changed");
        c.framerate.rows[last][col] = old;
    }
    check_claims(&sec, &c).unwrap();
}

#[test]
fn the_old_overclaim_is_caught() {
    // The text once said the first target was held "from frame 79 on" while only 6 of frames
    // 1-79 were within 10 %: a claim of that kind must fail against the data.
    let (doc, c, _) = data().unwrap();
    let sec = section(&doc, cc::BEGIN, cc::END).unwrap();
    let line = sec
        .lines()
        .find(|l| l.starts_with("- First target"))
        .unwrap();
    let fps = c.framerate.f64s("controlled").unwrap();
    let t = c.framerate.f64s("target").unwrap()[0];
    let switch = c.setting("switch_frame").unwrap() as usize;
    // Claim a frame from which a frame outside the band follows (if any), or one frame too late.
    let bad = (0..switch)
        .find(|&i| (i..switch).any(|j| (fps[j] / t - 1.0).abs() > cc::BAND))
        .unwrap_or(0);
    let claim = format!(
        "- First target, {t:.1} fps (frames 0–{}): 0 of {switch} frames within ±10 %; every frame from frame {bad} on (x)",
        switch - 1
    );
    let m = sec.replace(line, &claim);
    assert!(check_claims(&m, &c).is_err());
}
