//! Fuzzing the USD input: generated stages (grammar-built `.usda` text with meshes, creases,
//! corners, holes, schemes, `primvars:st`, time samples, transforms, composition arcs and typed
//! defects; the same text byte-mutated; byte-mutated `.usdc` crate files and `.usdz` archives,
//! from the fixtures and from grammar stages encoded by `openusd`'s writers; see
//! `subdiv_tests::fuzz_usd`) go through `read_cage`, the product's reading path, and every cage
//! built through the depth-1 tessellations the OBJ fuzzer runs (`subdiv_tests::fuzz_check`).
//! Each case is written to a file of its own extension in a temporary folder, because the
//! reader opens stages by path.
//!
//! Properties: nothing panics out of `read_cage` (a panic inside the third-party `openusd`
//! parser is caught at `subdiv-mesh`'s boundary and becomes `UsdError::ReaderPanic`, counted and
//! listed here as a parser defect, not a failure; one whose location is outside `openusd`, in
//! subdiv's own code or the standard library, is a failure);
//! no case runs over 60 s (a watchdog aborts the run, printing the case); every refusal is a
//! typed `UsdError` whose message starts with the file's path; every cage built tessellates to
//! finite output.
//!
//! The default run is small enough for CI. Environment, as for `fuzz_input`:
//! `SUBDIV_FUZZ_CASES` (default 5000), `SUBDIV_FUZZ_SEED` (default `0x05D0`, decimal or `0x`
//! hex), `SUBDIV_FUZZ_FIRST` (first case index; with `SUBDIV_FUZZ_CASES=1` it replays one case,
//! and `SUBDIV_FUZZ_KEEP=1` keeps its file, whose path is printed). Large runs, in release mode
//! (see docs/testing.md):
//!
//! ```text
//! SUBDIV_FUZZ_CASES=1000000 cargo test --release -p subdiv-tests --test fuzz_usd -- --nocapture
//! ```

use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use subdiv_tests::fuzz::{Rng, env_u64};
use subdiv_tests::fuzz_check::{Outcome, check_usd};
use subdiv_tests::fuzz_usd::{Seeds, UsdInput, usd_input};

const DEFAULT_SEED: u64 = 0x05D0;
const DEFAULT_CASES: u64 = 5000;
/// A case running longer than this is a hang (the largest inputs take milliseconds).
const HANG: Duration = Duration::from_secs(60);

/// The case now running, for the hang watchdog: (index, start, input).
type Current = Arc<Mutex<(u64, Instant, Option<UsdInput>)>>;

/// Aborts the process, printing the case, if one case runs longer than [`HANG`].
fn watchdog(current: Current, seed: u64, dir: PathBuf) {
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_secs(1));
            let (case, start, inp) = current.lock().unwrap().clone();
            if start.elapsed() > HANG {
                let (kind, shown) = inp.map_or(("?", String::new()), |i| (i.kind, shown(&i)));
                let _ = writeln!(
                    std::io::stderr(),
                    "fuzz_usd: HANG: case {case} ({kind}; SUBDIV_FUZZ_SEED={seed:#x} \
                     SUBDIV_FUZZ_FIRST={case} SUBDIV_FUZZ_CASES=1; the file is in {}) ran over \
                     {HANG:?}; input:\n{shown}",
                    dir.display()
                );
                std::process::exit(101);
            }
        }
    });
}

/// The start of an input for a report: text as text, binary as hex.
fn shown(i: &UsdInput) -> String {
    if i.ext == "usda" {
        String::from_utf8_lossy(&i.bytes)
            .chars()
            .take(1500)
            .collect()
    } else {
        let hex: Vec<String> = i
            .bytes
            .iter()
            .take(256)
            .map(|b| format!("{b:02x}"))
            .collect();
        format!("{} (first 256 bytes of {})", hex.join(" "), i.bytes.len())
    }
}

/// A distinct failure (or caught parser panic): how often and the first case showing it.
struct Seen {
    count: u64,
    case: u64,
    input: UsdInput,
    what: String,
}

/// Messages are grouped without digits and without the temporary path (one entry per bug).
fn key(what: &str, dir: &Path) -> String {
    let what = what.replace(&dir.display().to_string(), "");
    let first = what.lines().take(2).collect::<Vec<_>>().join(" ");
    first.chars().filter(|c| !c.is_ascii_digit()).collect()
}

/// A temporary folder of this process and test (the tests run in parallel, and each removes
/// its own folder).
fn temp_dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("subdiv-fuzz-usd-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
    d
}

#[test]
fn fuzz_usd() {
    let seed = env_u64("SUBDIV_FUZZ_SEED", DEFAULT_SEED);
    let cases = env_u64("SUBDIV_FUZZ_CASES", DEFAULT_CASES);
    let first = env_u64("SUBDIV_FUZZ_FIRST", 0);
    let keep = env_u64("SUBDIV_FUZZ_KEEP", 0) != 0;
    let seeds = Seeds::load();
    let dir = temp_dir("fuzz");
    let current: Current = Arc::new(Mutex::new((first, Instant::now(), None)));
    watchdog(current.clone(), seed, dir.clone());
    let t0 = Instant::now();
    let mut outcomes: BTreeMap<&str, u64> = BTreeMap::new();
    let mut by_ext: BTreeMap<String, u64> = BTreeMap::new();
    let mut failures: BTreeMap<String, Seen> = BTreeMap::new();
    let mut panics: BTreeMap<String, Seen> = BTreeMap::new();
    let mut slowest = (first, Duration::ZERO, "");
    for case in first..first + cases {
        let inp = usd_input(&mut Rng::for_case(seed, case), &seeds);
        let path = dir.join(format!("case.{}", inp.ext));
        std::fs::write(&path, &inp.bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        *current.lock().unwrap() = (case, Instant::now(), Some(inp.clone()));
        let note = |map: &mut BTreeMap<String, Seen>, what: String| {
            map.entry(key(&what, &dir))
                .or_insert(Seen {
                    count: 0,
                    case,
                    input: inp.clone(),
                    what,
                })
                .count += 1;
        };
        let started = Instant::now();
        let checked = check_usd(&path);
        let took = started.elapsed();
        if took > slowest.1 {
            slowest = (case, took, inp.kind);
        }
        match checked {
            Ok(o) => {
                let name = match (o.outcome, o.refusal) {
                    (Outcome::Tessellated, _) => "tessellated",
                    (_, Some(r)) => r,
                    (_, None) => "refused",
                };
                *outcomes.entry(name).or_default() += 1;
                *by_ext
                    .entry(format!(
                        "{} {}",
                        inp.ext,
                        if name == "tessellated" {
                            "tessellated"
                        } else {
                            "refused"
                        }
                    ))
                    .or_default() += 1;
                if let Some(p) = o.panic {
                    note(&mut panics, p);
                }
            }
            Err(f) => note(&mut failures, f.to_string()),
        }
        let done = case - first + 1;
        if done.is_multiple_of(50_000) {
            let _ = writeln!(
                std::io::stderr(),
                "fuzz_usd: {done} cases, {:.0}/s, {outcomes:?}, {} distinct failures",
                done as f64 / t0.elapsed().as_secs_f64(),
                failures.len()
            );
        }
    }
    let secs = t0.elapsed().as_secs_f64();
    if keep {
        println!(
            "fuzz_usd: the last case's file is kept in {}",
            dir.display()
        );
    } else {
        let _ = std::fs::remove_dir_all(&dir);
    }
    println!(
        "fuzz_usd: seed {seed:#x}, cases {first}..{}, {secs:.1} s ({:.0} cases/s), outcomes {outcomes:?}, by format {by_ext:?}, slowest case {} ({}, {:.3} s), {} distinct parser panics caught, {} distinct failures",
        first + cases,
        cases as f64 / secs,
        slowest.0,
        slowest.2,
        slowest.1.as_secs_f64(),
        panics.len(),
        failures.len()
    );
    for s in panics.values() {
        println!(
            "fuzz_usd: parser panic caught ({}x; first: case {}, {}): {}",
            s.count, s.case, s.input.kind, s.what
        );
    }
    report(seed, &failures);
}

/// Panics with every distinct failure, its first input and how to replay it.
fn report(seed: u64, failures: &BTreeMap<String, Seen>) {
    if failures.is_empty() {
        return;
    }
    let mut msg = String::new();
    for s in failures.values() {
        msg.push_str(&format!(
            "\n=== {} ({}x; first: case {}, {}; replay with SUBDIV_FUZZ_SEED={seed:#x} SUBDIV_FUZZ_FIRST={} SUBDIV_FUZZ_CASES=1)\n--- input ({} bytes, .{}):\n{}\n",
            s.what,
            s.count,
            s.case,
            s.input.kind,
            s.case,
            s.input.bytes.len(),
            s.input.ext,
            shown(&s.input)
        ));
    }
    panic!("fuzz_usd: {} distinct failures:{msg}", failures.len());
}

/// The checker tells good and refused stages apart, and every seed reads.
#[test]
fn harness_classifies_stages() {
    let dir = temp_dir("harness");
    let write = |name: &str, text: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let quad = b"#usda 1.0\ndef Mesh \"Q\"\n{\n    int[] faceVertexCounts = [4]\n    int[] faceVertexIndices = [0, 1, 2, 3]\n    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n}\n";
    let o = check_usd(&write("quad.usda", quad)).unwrap();
    assert_eq!(o.outcome, Outcome::Tessellated, "{o:?}");
    let o = check_usd(&write("junk.usda", b"#usda 1.0\ndef Mesh \"Q\" {{{")).unwrap();
    assert_eq!(o.refusal, Some("Open"), "{o:?}");
    let o = check_usd(&write("none.usda", b"#usda 1.0\ndef Xform \"X\"\n{\n}\n")).unwrap();
    assert_eq!(o.refusal, Some("NoMesh"), "{o:?}");
    let fixtures = subdiv_tests::fixtures().join("usd");
    for name in ["scene.usdc", "open_lefthanded.usdz"] {
        let o = check_usd(&fixtures.join(name)).unwrap();
        assert_eq!(o.outcome, Outcome::Tessellated, "{name}: {o:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
