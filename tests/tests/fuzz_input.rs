//! Fuzzing the input side: generated OBJ files (raw bytes, mutated text and grammar-built cages
//! with tags and defective topology) through the reader, validation, the non-manifold repair and
//! depth-1 tessellation. No stage may panic or hang, every refusal must be a typed error naming
//! its line, and every mesh built must tessellate to finite output (see
//! `subdiv_tests::fuzz_check`).
//!
//! The default run is small enough for CI. Environment:
//! `SUBDIV_FUZZ_CASES` (default 5000), `SUBDIV_FUZZ_SEED` (default `0x13F0`, decimal or `0x`
//! hex), `SUBDIV_FUZZ_FIRST` (first case index; with `SUBDIV_FUZZ_CASES=1` it replays one case).
//! Large runs, in release mode (see docs/testing.md):
//!
//! ```text
//! SUBDIV_FUZZ_CASES=1000000 cargo test --release -p subdiv-tests --test fuzz_input -- --nocapture
//! ```

use std::collections::BTreeMap;
use std::io::Write as _;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use subdiv_tests::fuzz::{Rng, env_u64, input};
use subdiv_tests::fuzz_check::{Outcome, check, guard};

const DEFAULT_SEED: u64 = 0x13F0;
const DEFAULT_CASES: u64 = 5000;
/// A case running longer than this is a hang (the largest inputs take milliseconds).
const HANG: Duration = Duration::from_secs(60);

/// The case now running, for the hang watchdog: (index, start, input).
type Current = Arc<Mutex<(u64, Instant, Vec<u8>)>>;

/// Aborts the process, printing the case, if one case runs longer than [`HANG`].
fn watchdog(current: Current, seed: u64) {
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_secs(1));
            let (case, start, bytes) = current.lock().unwrap().clone();
            if start.elapsed() > HANG {
                let _ = writeln!(
                    std::io::stderr(),
                    "fuzz_input: HANG: case {case} (SUBDIV_FUZZ_SEED={seed:#x} SUBDIV_FUZZ_FIRST={case} \
                     SUBDIV_FUZZ_CASES=1) ran over {HANG:?}; input:\n{}",
                    String::from_utf8_lossy(&bytes)
                );
                std::process::exit(101);
            }
        }
    });
}

/// A distinct failure: how often it happened and the first case showing it.
struct Seen {
    count: u64,
    case: u64,
    kind: &'static str,
    input: Vec<u8>,
    what: String,
}

/// Failures are grouped by stage and message without digits (one entry per bug, not per input).
fn key(stage: &str, what: &str) -> String {
    let first = what.lines().take(2).collect::<Vec<_>>().join(" ");
    let first: String = first.chars().filter(|c| !c.is_ascii_digit()).collect();
    format!("{stage}: {first}")
}

#[test]
fn fuzz_input() {
    let seed = env_u64("SUBDIV_FUZZ_SEED", DEFAULT_SEED);
    let cases = env_u64("SUBDIV_FUZZ_CASES", DEFAULT_CASES);
    let first = env_u64("SUBDIV_FUZZ_FIRST", 0);
    let current: Current = Arc::new(Mutex::new((first, Instant::now(), Vec::new())));
    watchdog(current.clone(), seed);
    let t0 = Instant::now();
    let mut outcomes: BTreeMap<&str, u64> = BTreeMap::new();
    let mut failures: BTreeMap<String, Seen> = BTreeMap::new();
    for case in first..first + cases {
        let inp = input(&mut Rng::for_case(seed, case));
        *current.lock().unwrap() = (case, Instant::now(), inp.bytes.clone());
        match check(&inp.bytes) {
            Ok(o) => {
                let name = match o {
                    Outcome::ParseRefused => "parse refused",
                    Outcome::MeshRefused => "mesh refused",
                    Outcome::Tessellated => "tessellated",
                };
                *outcomes.entry(name).or_default() += 1;
            }
            Err(f) => {
                let e = failures.entry(key(f.stage, &f.what)).or_insert(Seen {
                    count: 0,
                    case,
                    kind: inp.kind,
                    input: inp.bytes.clone(),
                    what: f.to_string(),
                });
                e.count += 1;
            }
        }
        let done = case - first + 1;
        if done.is_multiple_of(100_000) {
            let _ = writeln!(
                std::io::stderr(),
                "fuzz_input: {done} cases, {:.0}/s",
                done as f64 / t0.elapsed().as_secs_f64()
            );
        }
    }
    let secs = t0.elapsed().as_secs_f64();
    println!(
        "fuzz_input: seed {seed:#x}, cases {first}..{}, {secs:.1} s ({:.0} cases/s), outcomes {outcomes:?}, {} distinct failures",
        first + cases,
        cases as f64 / secs,
        failures.len()
    );
    report(seed, &failures);
}

/// Panics with every distinct failure, its first input and how to replay it.
fn report(seed: u64, failures: &BTreeMap<String, Seen>) {
    if failures.is_empty() {
        return;
    }
    let mut msg = String::new();
    for s in failures.values() {
        let text = String::from_utf8_lossy(&s.input);
        let shown: String = text.chars().take(1500).collect();
        msg.push_str(&format!(
            "\n=== {} ({}x; first: case {}, {}; replay with SUBDIV_FUZZ_SEED={seed:#x} SUBDIV_FUZZ_FIRST={} SUBDIV_FUZZ_CASES=1)\n--- input ({} bytes):\n{shown}\n",
            s.what,
            s.count,
            s.case,
            s.kind,
            s.case,
            s.input.len()
        ));
    }
    panic!("fuzz_input: {} distinct failures:{msg}", failures.len());
}

/// The harness itself can fail: a panic inside a stage is caught and reported with its
/// location, and the checker tells good, refused and invalid inputs apart.
#[test]
fn harness_detects_panics_and_classifies_inputs() {
    let f = guard("demo", || -> u32 { panic!("boom {}", 7) }).unwrap_err();
    assert_eq!(f.stage, "demo");
    // (The location, "panicked at ...fuzz_input.rs", is added unless the concurrent test's
    // guard took the shared hook slot first; the message is always there.)
    assert!(
        f.what.starts_with("panic: ") && f.what.contains("boom 7"),
        "{f}"
    );
    assert_eq!(guard("demo", || 3).unwrap(), 3);

    let quad = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    assert_eq!(check(quad), Ok(Outcome::Tessellated));
    assert_eq!(check(b"v 0 0\n"), Ok(Outcome::ParseRefused));
    assert_eq!(
        check(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n"),
        Ok(Outcome::MeshRefused)
    );
    // A bow-tie is refused as read and tessellated after the repair.
    let bowtie = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n";
    assert_eq!(check(bowtie), Ok(Outcome::Tessellated));
}

/// Inputs that once broke a stage (found by the fuzzer); each stays fixed.
#[test]
fn regressions() {
    for (name, text) in REGRESSIONS {
        assert!(
            check(text.as_bytes()).is_ok(),
            "{name}: {:?}",
            check(text.as_bytes())
        );
    }
}

const REGRESSIONS: &[(&str, &str)] = &[
    (
        "tag counts overflow usize",
        "t crease 18446744073709551615/1/0\n",
    ),
    (
        "tag counts overflow to the argument count",
        "v 0 0 0\nt corner 18446744073709551615/18446744073709551615/2 1 2\n",
    ),
    (
        "coordinate near f32::MAX",
        "v 0 0 0\nv 1 0 0\nv 3.4028235e38 1 0\nv 0 1 0\nf 1 2 3 4\n",
    ),
    (
        "n-gon with a coordinate near f32::MAX",
        "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 -3.4e38\nv 0 1 0\nf 1 2 3 4 5\n",
    ),
    (
        "Loop on two triangles on the same vertices",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 3 2 1\n",
    ),
];
