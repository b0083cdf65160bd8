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

/// The cells of the table row of `text` that starts with `prefix`.
fn row<'a>(text: &'a str, prefix: &str) -> Result<Vec<&'a str>> {
    let line = text
        .lines()
        .find(|l| l.starts_with(prefix))
        .with_context(|| format!("no row {prefix:?}"))?;
    Ok(line
        .split('|')
        .map(str::trim)
        .filter(|c| !c.is_empty())
        .collect())
}

/// The median of `v` (upper), recomputed here.
fn med(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
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
    // Fig. 7: each phase of each controller in the paper's scenario.
    let target = d.framerate.f64s("target")?;
    let switch = d.setting("switch_frame")? as usize;
    let n = target.len();
    let mut first_after_switch = Vec::new();
    for (col, name) in [("budget", "| predictive |"), ("paper", "| paper |")] {
        let fps = d.framerate.f64s(col)?;
        let rows: Vec<&str> = text.lines().filter(|l| l.starts_with(name)).collect();
        ensure!(rows.len() == 2, "{name}: {} rows, not 2", rows.len());
        for (k, (lo, hi)) in [(0, switch), (switch, n)].into_iter().enumerate() {
            let t = target[lo];
            let cells = row(rows[k], name)?;
            ensure!(
                (cells[1].parse::<f64>()? - t).abs() < 0.05,
                "{}: the CSV's target is {t}",
                rows[k]
            );
            let inside: Vec<bool> = (lo..hi)
                .map(|i| fps[i] >= 0.9 * t && fps[i] <= 1.1 * t)
                .collect();
            let count = inside.iter().filter(|&&x| x).count();
            ensure!(
                cells[2] == format!("{count} of {}", hi - lo),
                "{}: {count} frames of {lo}..{hi} lie within 10 % of {t}",
                rows[k]
            );
            let first = inside.iter().position(|&x| x);
            let stated = cells[3];
            ensure!(
                first.map_or("never".to_string(), |f| f.to_string()) == stated,
                "{}: the first frame within 10 % is {first:?} frames into the phase",
                rows[k]
            );
            if k == 1 {
                first_after_switch.push(first);
            }
        }
    }
    let say = |f: Option<usize>| f.map_or("no".to_string(), |f| f.to_string());
    let claim = format!(
        "the predictive controller's first frame within ±10 % of the new target comes {} frames after it",
        say(first_after_switch[0])
    );
    ensure!(text.contains(&claim), "the text does not say: {claim}");
    let claim = format!("the paper's controller's {}.", say(first_after_switch[1]));
    ensure!(text.contains(&claim), "the text does not say: {claim}");
    // A level of quality for free: each verdict against the next uniform depth's errors.
    let n5 = d.triangles.rows.len();
    for (k, depth) in [(2usize, 3usize), (3, 4)] {
        let pick = |config: &str, range: std::ops::Range<usize>| -> Result<(f64, f64)> {
            let t = d.error.filter("config", config)?;
            let frames = t.f64s("frame")?;
            let keep = |v: Vec<f64>| -> Vec<f64> {
                v.into_iter()
                    .zip(&frames)
                    .filter(|(_, f)| range.contains(&(**f as usize)))
                    .map(|(x, _)| x)
                    .collect()
            };
            let sil = keep(t.f64s("silhouette_px_max")?);
            let shade = keep(t.f64s("shading_deg_p99")?);
            Ok((
                sil.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                med(shade),
            ))
        };
        let h = pick(&format!("held{k}"), 0..n)?;
        let u = pick(&format!("uniform{depth}"), 0..n5)?;
        let verdict = if h.0 <= u.0 && h.1 <= u.1 {
            "no worse"
        } else {
            "worse"
        };
        let claim = format!(
            "At uniform depth {k}'s rate the predictive picture is {verdict} than uniform depth {depth}'s"
        );
        ensure!(text.contains(&claim), "the text does not say: {claim}");
    }
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
    // Move the last frame of each phase of each controller across the band's edge (in if it
    // was out, out if it was in): the stated frame counts are no longer what the data show.
    let tcol = c.framerate.col("target").unwrap();
    let switch = c.setting("switch_frame").unwrap() as usize;
    let n = c.framerate.rows.len();
    for name in ["budget", "paper"] {
        let col = c.framerate.col(name).unwrap();
        for last in [switch - 1, n - 1] {
            let t: f64 = c.framerate.rows[last][tcol].parse().unwrap();
            let old = c.framerate.rows[last][col].clone();
            let was_in = (old.parse::<f64>().unwrap() / t - 1.0).abs() <= cc::BAND;
            c.framerate.rows[last][col] = format!("{}", if was_in { t * 1.5 } else { t });
            assert!(
                check_claims(&sec, &c).is_err(),
                "{name} frame {last} changed"
            );
            c.framerate.rows[last][col] = old;
        }
    }
    check_claims(&sec, &c).unwrap();
}

#[test]
fn a_first_frame_claimed_too_early_is_caught() {
    // Claim the predictive controller met the new target right at the switch when the data
    // say otherwise (or one frame later when it did): the check must fail.
    let (doc, c, _) = data().unwrap();
    let sec = section(&doc, cc::BEGIN, cc::END).unwrap();
    let fps = c.framerate.f64s("budget").unwrap();
    let t = c.framerate.f64s("target").unwrap();
    let switch = c.setting("switch_frame").unwrap() as usize;
    let at_switch = (fps[switch] / t[switch] - 1.0).abs() <= cc::BAND;
    let wrong = if at_switch {
        "comes 1 frames after it"
    } else {
        "comes 0 frames after it"
    };
    let right = sec
        .lines()
        .find(|l| l.contains("first frame within ±10 % of the new target comes"))
        .unwrap();
    let at = right.find("comes ").unwrap();
    let end = right[at..].find(" after it").unwrap() + at + " after it".len();
    let m = sec.replace(&right[at..end], wrong);
    assert!(check_claims(&m, &c).is_err());
}
