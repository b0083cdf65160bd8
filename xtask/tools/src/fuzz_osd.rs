//! `cargo xtask fuzz-osd [--cages N] [--seed S] [--levels A..B] [--index I] [--fvar]`: differential
//! testing against OpenSubdiv 3.5 (Debian `libosd-dev`) on random cages.
//!
//! Compiles `xtask/osd/ref_osd.cpp` once into `<target>/osd/`, generates cages with
//! `subdiv_tests::osd_gen::random_cage(seed, index)`, writes each to `<target>/fuzz-osd/`, runs
//! `ref_osd` on it at every level of `--levels` (default 1..4; with semi-sharp creases it takes
//! the limit where they have run out) and compares subdiv's uniform tessellation
//! (`subdiv_rules::tessellate_uniform`) and the slate tessellator of its scheme with it
//! (`subdiv_tests::osd_compare`: counts, faces, positions within 1e-5 x diagonal, smooth normals
//! within 0.05 degrees), and subdiv's exact evaluation at random points with OpenSubdiv's
//! `Bfr::Surface` (`fuzz_eval`). A disagreeing cage is printed with its seed and index, shrunk (faces
//! and tags dropped while it still disagrees) and written to
//! `<target>/fuzz-osd/failing-<seed>-<index>.obj`; the smallest also to `failing-<seed>.obj`.
//! Every cage the generator draws is meant to be valid: a finished cage that subdiv refused
//! while drawing (`Draw::refused`) or a refused sharpened form (`Draw::fell_back`) is a
//! disagreement of that index, shrunk and written like any other.
//! The last line is `fuzz-osd: <passed>/<total> cages agree (<r> refused, <f> fell back)`, where
//! `refused` counts the indices at which subdiv refused a cage drawn valid and `fell back` those
//! whose sharpened form it refused; any disagreement exits non-zero.
//! With `--fvar` each cage also gets random UV seams and a random face-varying option
//! (`subdiv_tests::osd_fvar::cage_obj_with_uvs`), compared with `xtask/osd/ref_fvar.cpp`
//! (OpenSubdiv's `InterpolateFaceVarying`, then `LimitFaceVarying` of the refined values against
//! `subdiv_rules::limit_face_varying`) at every level; the `cargo xtask test` round does this
//! too.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use subdiv_tests::Reference;
use subdiv_tests::osd_cage::OsdCage;
use subdiv_tests::osd_compare::{Tessellator, compare};
use subdiv_tests::osd_fvar::{cage_obj_with_uvs, compare_fvar, compare_fvar_values, parse_fvar};
use subdiv_tests::osd_gen::{Draw, draw_cage};

use xtask::osd::{INSTALL, osd_present};

/// Normal tolerance (degrees) where the surface is smooth.
const NORMAL_DEG: f64 = 0.05;
/// The round `cargo xtask test` runs.
pub const SHORT_ROUND: Options = Options {
    cages: 300,
    seed: 1,
    levels: (1, 4),
    index: None,
    fvar: true,
};

/// Command-line options.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    cages: u64,
    seed: u64,
    levels: (u32, u32),
    /// Only this cage (replay).
    index: Option<u64>,
    /// Also compare face-varying refinement (random UV seams and option per cage, `ref_fvar`).
    fvar: bool,
}

impl Options {
    pub fn parse(args: &[String]) -> Result<Options> {
        let mut o = Options {
            cages: 1000,
            fvar: false,
            ..SHORT_ROUND
        };
        let mut it = args.iter();
        while let Some(a) = it.next() {
            let mut value = || it.next().with_context(|| format!("{a} needs a value"));
            match a.as_str() {
                "--cages" => o.cages = value()?.parse().context("--cages N")?,
                "--seed" => o.seed = value()?.parse().context("--seed S")?,
                "--index" => o.index = Some(value()?.parse().context("--index I")?),
                "--fvar" => o.fvar = true,
                "--levels" => {
                    let v = value()?;
                    let (a, b) = v.split_once("..").unwrap_or((v, v));
                    o.levels = (a.parse()?, b.trim_start_matches('=').parse()?);
                    if o.levels.0 < 1 || o.levels.1 < o.levels.0 || o.levels.1 > 6 {
                        bail!("--levels A..B with 1 <= A <= B <= 6");
                    }
                }
                _ => bail!("unknown argument {a}"),
            }
        }
        Ok(o)
    }
}

/// One disagreement.
#[derive(Debug, Clone)]
struct Failure {
    index: u64,
    level: u32,
    what: String,
    /// The cage that disagrees (a refused one where subdiv refused a cage drawn valid).
    cage: OsdCage,
}

/// What a round counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    pub total: u64,
    pub agreed: u64,
    /// Indices at which subdiv refused a finished cage that the generator drew valid.
    pub refused: u64,
    /// Indices whose sharpened form subdiv refused (the unsharpened cage was drawn instead).
    pub fell_back: u64,
}

impl Tally {
    /// The summary line.
    pub fn line(&self) -> String {
        format!(
            "fuzz-osd: {}/{} cages agree ({} refused, {} fell back)",
            self.agreed, self.total, self.refused, self.fell_back
        )
    }

    pub fn all_agree(&self) -> bool {
        self.agreed == self.total
    }
}

/// The disagreement a draw carries before any comparison: a refusal of a cage the generator
/// meant to be valid (the refused cage and the error), `None` when subdiv took every cage.
fn draw_refusal(draw: &Draw) -> Option<(OsdCage, String)> {
    if let Some(r) = draw.refused.first() {
        return Some((
            r.cage.clone(),
            format!(
                "subdiv refuses a cage drawn valid ({} redraw(s)): {}",
                draw.refused.len(),
                r.error
            ),
        ));
    }
    draw.fell_back.as_ref().map(|r| {
        (
            r.cage.clone(),
            format!(
                "subdiv refuses the sharpened form of a cage drawn valid (fell back to the unsharpened cage): {}",
                r.error
            ),
        )
    })
}

/// The command: exits non-zero on a disagreement, with the summary as the last line.
pub fn command(root: &Path, o: &Options) -> Result<()> {
    if !osd_present() {
        println!(
            "fuzz-osd: skipped: OpenSubdiv 3.5 (Debian libosd-dev) is not installed. Install it with\n    sudo {INSTALL}"
        );
        return Ok(());
    }
    let tally = run(root, o)?;
    println!("{}", tally.line());
    if !tally.all_agree() {
        std::process::exit(1);
    }
    Ok(())
}

/// The short round of `cargo xtask test` (OpenSubdiv installed: see `xtask::osd::ensure_osd`).
pub fn short_round(root: &Path) -> Result<()> {
    let tally = run(root, &SHORT_ROUND)?;
    println!("{}", tally.line());
    if !tally.all_agree() {
        bail!(
            "fuzz-osd: {} of {} random cages disagree with OpenSubdiv",
            tally.total - tally.agreed,
            tally.total
        );
    }
    Ok(())
}

/// Compiles `xtask/osd/<name>.cpp` unless the binary is newer than every file in `xtask/osd`
/// (its source, the shared header `obj_cage.h`, and the sources one harness includes from
/// another, as `bench_animate.cpp` includes `bench_osd.cpp`).
pub(crate) fn build_harness(root: &Path, name: &str) -> Result<PathBuf> {
    build_harness_with(root, name, &["-O2", "-std=c++14"], "")
}

/// [`build_harness`] with the compiler flags `flags`, the binary named `<name><suffix>` (a
/// binary built with other flags is never reused).
pub(crate) fn build_harness_with(
    root: &Path,
    name: &str,
    flags: &[&str],
    suffix: &str,
) -> Result<PathBuf> {
    let src = root.join(format!("xtask/osd/{name}.cpp"));
    let exe = xtask::target_dir().join(format!("osd/{name}{suffix}"));
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    let newest = std::fs::read_dir(root.join("xtask/osd"))?
        .filter_map(|e| e.ok())
        .filter_map(|e| modified(&e.path()))
        .max();
    if modified(&exe).is_some_and(|e| newest.is_some_and(|s| e >= s)) {
        return Ok(exe);
    }
    std::fs::create_dir_all(exe.parent().expect("has a parent"))?;
    println!("xtask: compiling {}", src.display());
    crate::bench_osd::output(
        Command::new("g++")
            .args(flags)
            .arg("-o")
            .arg(&exe)
            .arg(&src)
            .arg("-losdCPU"),
    )
    .with_context(|| format!("compiling {name} (is g++ installed? apt-get install -y g++)"))?;
    Ok(exe)
}

struct Harness {
    exe: PathBuf,
    /// `ref_eval`, the evaluation reference (`fuzz_eval`).
    eval_exe: PathBuf,
    /// Cages where Bfr is off the limit surface, and where its harness failed.
    bfr_off: AtomicU64,
    bfr_failed: AtomicU64,
    /// `ref_fvar`, the face-varying reference (with `--fvar`).
    fvar_exe: Option<PathBuf>,
    dir: PathBuf,
    seed: u64,
}

impl Harness {
    /// Compares `cage` at `level`: `Err` describes the first disagreement.
    fn check_level(&self, cage: &OsdCage, path: &Path, level: u32) -> Result<(), String> {
        let mesh = cage
            .mesh()
            .map_err(|e| format!("subdiv refuses the cage: {e}"))?;
        let out = Command::new(&self.exe)
            .arg(path)
            .arg(level.to_string())
            .arg(cage.scheme_name())
            .arg("local")
            .output()
            .map_err(|e| format!("could not run ref_osd: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "ref_osd failed: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
        let reference = Reference::parse(&String::from_utf8_lossy(&out.stdout))?;
        let depth = level as subdiv_rules::Depth;
        compare(&mesh, depth, &reference, Tessellator::Uniform, NORMAL_DEG)
            .map_err(|e| format!("uniform: {e}"))?;
        compare(&mesh, depth, &reference, Tessellator::Slate, NORMAL_DEG)
            .map_err(|e| format!("slate: {e}"))?;
        if self.fvar_exe.is_some() {
            self.check_fvar(cage, path, level)
                .map_err(|e| format!("face-varying: {e}"))?;
        }
        Ok(())
    }

    /// The cage with random UV seams and option (`cage_obj_with_uvs`, seeded by the cage's
    /// text) against `ref_fvar` at `level`.
    fn check_fvar(&self, cage: &OsdCage, path: &Path, level: u32) -> Result<(), String> {
        let text = cage.to_obj();
        let seed = text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        });
        let uv_text = cage_obj_with_uvs(cage, seed);
        let uv_path = path.with_extension("uv.obj");
        std::fs::write(&uv_path, &uv_text).map_err(|e| format!("{}: {e}", uv_path.display()))?;
        let Some(exe) = &self.fvar_exe else {
            return Ok(());
        };
        let mut soup = subdiv_mesh::parse_obj(&uv_text).map_err(|e| e.to_string())?;
        // As subdiv reads the cage (non-manifold cages refined as OpenSubdiv refines them).
        soup.split_nonmanifold().map_err(|e| e.to_string())?;
        let soup = soup;
        let run = |limit: bool| -> Result<Vec<Vec<f64>>, String> {
            let mut cmd = Command::new(exe);
            cmd.arg(&uv_path)
                .arg(level.to_string())
                .arg(cage.scheme_name())
                .arg(soup.options.fvar.tag().to_string());
            if limit {
                cmd.arg("limit");
            }
            let out = cmd
                .output()
                .map_err(|e| format!("could not run ref_fvar: {e}"))?;
            if !out.status.success() {
                return Err(format!(
                    "ref_fvar failed: {}",
                    String::from_utf8_lossy(&out.stderr).trim()
                ));
            }
            Ok(parse_fvar(&String::from_utf8_lossy(&out.stdout)))
        };
        let mesh = subdiv_mesh::Mesh::from_soup(&soup).map_err(|e| e.to_string())?;
        let scheme = if cage.loop_scheme {
            subdiv_rules::Scheme::Loop
        } else {
            subdiv_rules::Scheme::CatmullClark
        };
        let depth = level as subdiv_rules::Depth;
        let refined =
            subdiv_rules::refine_uniform_levels(&mesh, scheme, depth).map_err(|e| e.to_string())?;
        compare_fvar(&mesh, scheme, depth, &refined, &run(false)?)
            .map_err(|e| format!("option {}: {e}", soup.options.fvar.name()))?;
        let limit = subdiv_rules::limit_face_varying(&refined, scheme).unwrap_or_default();
        compare_fvar_values(&mesh, scheme, depth, &refined, &limit, &run(true)?)
            .map_err(|e| format!("option {} (limit): {e}", soup.options.fvar.name()))?;
        let _ = std::fs::remove_file(&uv_path);
        Ok(())
    }

    /// Writes `cage` to `name.obj` and compares it at `levels`; the first failing level.
    fn check(&self, cage: &OsdCage, name: &str, levels: (u32, u32)) -> Result<(), (u32, String)> {
        let path = self.dir.join(format!("{name}.obj"));
        std::fs::write(&path, cage.to_obj())
            .map_err(|e| (0, format!("{}: {e}", path.display())))?;
        for level in levels.0..=levels.1 {
            self.check_level(cage, &path, level)
                .map_err(|e| (level, e))?;
        }
        match crate::fuzz_eval::check(&self.eval_exe, &self.dir, cage, name) {
            Ok(crate::fuzz_eval::Outcome::Agrees) => {}
            Ok(crate::fuzz_eval::Outcome::BfrOff(why)) => {
                println!("fuzz-osd: note: {name}: Bfr is off the limit surface: {why}");
                self.bfr_off.fetch_add(1, Ordering::Relaxed);
            }
            Ok(crate::fuzz_eval::Outcome::BfrFailed(why)) => {
                println!("fuzz-osd: note: {name}: ref_eval failed: {why}");
                self.bfr_failed.fetch_add(1, Ordering::Relaxed);
            }
            Err(e) => return Err((levels.0, format!("evaluation: {e}"))),
        }
        let _ = std::fs::remove_file(&path);
        Ok(())
    }

    /// Drops faces and tags while the cage still disagrees at `level`; the smallest cage and
    /// its disagreement.
    fn shrink(&self, mut cage: OsdCage, level: u32, mut what: String) -> (OsdCage, String) {
        let name = format!("shrink-{}", self.seed);
        'outer: loop {
            for c in cage.reductions() {
                if let Err((_, w)) = self.check(&c, &name, (level, level)) {
                    cage = c;
                    what = w;
                    continue 'outer;
                }
            }
            let _ = std::fs::remove_file(self.dir.join(format!("{name}.obj")));
            return (cage, what);
        }
    }
}

/// Runs the round and counts it.
fn run(root: &Path, o: &Options) -> Result<Tally> {
    let harness = Harness {
        exe: build_harness(root, "ref_osd")?,
        eval_exe: build_harness(root, "ref_eval")?,
        bfr_off: AtomicU64::new(0),
        bfr_failed: AtomicU64::new(0),
        fvar_exe: if o.fvar {
            Some(build_harness(root, "ref_fvar")?)
        } else {
            None
        },
        dir: xtask::target_dir().join("fuzz-osd"),
        seed: o.seed,
    };
    std::fs::create_dir_all(&harness.dir)?;
    let indices: Vec<u64> = match o.index {
        Some(i) => vec![i],
        None => (0..o.cages).collect(),
    };
    let start = Instant::now();
    let next = AtomicU64::new(0);
    let (refused, fell_back) = (AtomicU64::new(0), AtomicU64::new(0));
    let failures = Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .min(indices.len().max(1));
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&index) = indices.get(k as usize) else {
                        break;
                    };
                    let draw = draw_cage(o.seed, index);
                    refused.fetch_add(u64::from(!draw.refused.is_empty()), Ordering::Relaxed);
                    fell_back.fetch_add(u64::from(draw.fell_back.is_some()), Ordering::Relaxed);
                    let name = format!("cage-{}-{index}", o.seed);
                    let failed = match draw_refusal(&draw) {
                        Some((cage, what)) => Some((cage, o.levels.0, what)),
                        None => harness
                            .check(&draw.cage, &name, o.levels)
                            .err()
                            .map(|(level, what)| (draw.cage, level, what)),
                    };
                    if let Some((cage, level, what)) = failed {
                        println!(
                            "fuzz-osd: DISAGREE seed {} cage {index} level {level} ({}): {what}",
                            o.seed,
                            cage.features()
                        );
                        failures.lock().expect("no panic").push(Failure {
                            index,
                            level,
                            what,
                            cage,
                        });
                    }
                    if (k + 1).is_multiple_of(1000) {
                        eprintln!(
                            "fuzz-osd: {} cages, {:.0} s",
                            k + 1,
                            start.elapsed().as_secs_f64()
                        );
                    }
                }
            });
        }
    });
    let mut failures = failures.into_inner().expect("no panic");
    failures.sort_by_key(|f| f.index);
    report(&harness, o, &failures)?;
    let total = indices.len() as u64;
    println!(
        "fuzz-osd: evaluation: Bfr off the limit surface on {} cages (shown by deep refinement), its harness failed on {}",
        harness.bfr_off.load(Ordering::Relaxed),
        harness.bfr_failed.load(Ordering::Relaxed)
    );
    println!(
        "fuzz-osd: seed {} levels {}..{}: {} cages in {:.1} s ({workers} threads)",
        o.seed,
        o.levels.0,
        o.levels.1,
        total,
        start.elapsed().as_secs_f64()
    );
    Ok(Tally {
        total,
        agreed: total - failures.len() as u64,
        refused: refused.into_inner(),
        fell_back: fell_back.into_inner(),
    })
}

/// Shrinks up to eight failing cages and writes them; the smallest also as `failing-<seed>.obj`.
fn report(h: &Harness, o: &Options, failures: &[Failure]) -> Result<()> {
    let mut smallest: Option<OsdCage> = None;
    for f in failures.iter().take(8) {
        let (small, what) = h.shrink(f.cage.clone(), f.level, f.what.clone());
        let path = h.dir.join(format!("failing-{}-{}.obj", o.seed, f.index));
        let note = format!(
            "# fuzz-osd: seed {} cage {} level {} ({})\n# {}\n",
            o.seed,
            f.index,
            f.level,
            small.features(),
            what.lines().next().unwrap_or("")
        );
        std::fs::write(&path, note + &small.to_obj())?;
        println!(
            "fuzz-osd: seed {} cage {} shrunk to {} faces ({}): {}\n    {what}",
            o.seed,
            f.index,
            small.faces.len(),
            small.features(),
            path.display()
        );
        if smallest
            .as_ref()
            .is_none_or(|s| small.faces.len() < s.faces.len())
        {
            std::fs::copy(&path, h.dir.join(format!("failing-{}.obj", o.seed)))?;
            smallest = Some(small);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_tests::osd_gen::{Refusal, draw_cage_with};

    /// A refusal while drawing, or of the sharpened form, is a disagreement carrying the
    /// refused cage; a draw without one is compared as usual.
    #[test]
    fn refusals_are_disagreements() {
        let calls = std::cell::Cell::new(0);
        let draw = draw_cage_with(1, 0, &|_| {
            calls.set(calls.get() + 1);
            if calls.get() == 1 {
                Err("no".into())
            } else {
                Ok(())
            }
        });
        let (cage, what) = draw_refusal(&draw).expect("a disagreement");
        assert_eq!(cage, draw.refused[0].cage);
        assert!(
            what.contains("refuses a cage drawn valid") && what.ends_with("no"),
            "{what}"
        );
        let sharp = Draw {
            fell_back: Some(Refusal {
                cage: draw.cage.clone(),
                error: "sharp".into(),
            }),
            refused: Vec::new(),
            ..draw.clone()
        };
        let (_, what) = draw_refusal(&sharp).expect("a disagreement");
        assert!(what.contains("fell back"), "{what}");
        let clean = Draw {
            refused: Vec::new(),
            fell_back: None,
            ..draw
        };
        assert!(draw_refusal(&clean).is_none());
        let t = Tally {
            total: 10,
            agreed: 8,
            refused: 1,
            fell_back: 1,
        };
        assert_eq!(
            t.line(),
            "fuzz-osd: 8/10 cages agree (1 refused, 1 fell back)"
        );
        assert!(!t.all_agree());
    }
}
