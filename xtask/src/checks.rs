//! The checks of `cargo xtask test` and their tally: each check passes, fails, or could not run.
//!
//! A check that cannot run (a test dependency missing and not installable here) fails the run
//! under `CI=true`, with its reason: CI must never report work it did not do. Outside CI it is
//! skipped and named. The last line is always
//! `xtask: N passed, F failed, K skipped (<names>)` (the names only when K > 0).

use anyhow::{Result, bail};

/// What became of one check.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    Passed,
    Failed(String),
    Skipped(String),
}

/// The checks of one run, in order.
#[derive(Debug)]
pub struct Checks {
    /// `CI=true`: a check that cannot run fails.
    ci: bool,
    results: Vec<(&'static str, Outcome)>,
}

/// Whether this process runs under CI (`CI=true` or `CI=1`, as CI services set it).
pub fn under_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| ci_value(&v))
}

/// Whether a value of `CI` means CI.
fn ci_value(v: &str) -> bool {
    v.eq_ignore_ascii_case("true") || v == "1"
}

impl Checks {
    pub fn new(ci: bool) -> Checks {
        Checks {
            ci,
            results: Vec::new(),
        }
    }

    /// Records a check that ran: passed on `Ok`, failed with the error otherwise.
    pub fn record(&mut self, name: &'static str, result: Result<()>) {
        let outcome = match result {
            Ok(()) => Outcome::Passed,
            Err(e) => Outcome::Failed(format!("{e:#}")),
        };
        self.push(name, outcome);
    }

    /// Records a check that cannot run, for `why`: a failure under CI, a skip otherwise.
    pub fn unavailable(&mut self, name: &'static str, why: &str) {
        let outcome = if self.ci {
            Outcome::Failed(format!("cannot run under CI=true: {why}"))
        } else {
            Outcome::Skipped(why.to_string())
        };
        self.push(name, outcome);
    }

    fn push(&mut self, name: &'static str, outcome: Outcome) {
        match &outcome {
            Outcome::Passed => eprintln!("xtask: {name}: passed"),
            Outcome::Failed(why) => eprintln!("xtask: {name}: FAILED: {why}"),
            Outcome::Skipped(why) => eprintln!("xtask: {name}: skipped: {why}"),
        }
        self.results.push((name, outcome));
    }

    #[cfg(test)]
    pub fn outcome(&self, name: &str) -> Option<&Outcome> {
        self.results
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, o)| o)
    }

    /// `xtask: N passed, F failed, K skipped (<names>)`.
    pub fn summary(&self) -> String {
        let count = |f: fn(&Outcome) -> bool| self.results.iter().filter(|(_, o)| f(o)).count();
        let passed = count(|o| matches!(o, Outcome::Passed));
        let failed = count(|o| matches!(o, Outcome::Failed(_)));
        let skipped: Vec<&str> = self
            .results
            .iter()
            .filter(|(_, o)| matches!(o, Outcome::Skipped(_)))
            .map(|(n, _)| *n)
            .collect();
        let mut line = format!(
            "xtask: {passed} passed, {failed} failed, {} skipped",
            skipped.len()
        );
        if !skipped.is_empty() {
            line.push_str(&format!(" ({})", skipped.join(", ")));
        }
        line
    }

    /// Prints the failures and the summary line (last, on stdout); an error when a check failed.
    pub fn finish(&self) -> Result<()> {
        let failed: Vec<String> = self
            .results
            .iter()
            .filter_map(|(n, o)| match o {
                Outcome::Failed(why) => Some(format!("{n}: {why}")),
                _ => None,
            })
            .collect();
        for f in &failed {
            eprintln!("xtask: FAILED {f}");
        }
        println!("{}", self.summary());
        if !failed.is_empty() {
            bail!("{} check(s) failed", failed.len());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vulkan::{Installer, ensure_optional};

    /// A machine with or without apt and root, whose installs succeed or fail.
    struct Machine {
        apt: bool,
        root: bool,
        install_works: bool,
    }

    impl Installer for Machine {
        fn has_apt(&self) -> bool {
            self.apt
        }
        fn is_root(&self) -> bool {
            self.root
        }
        fn run(&self, _cmd: &str) -> bool {
            self.install_works
        }
    }

    const MISSING: [Machine; 3] = [
        Machine {
            apt: false,
            root: true,
            install_works: true,
        },
        Machine {
            apt: true,
            root: false,
            install_works: true,
        },
        Machine {
            apt: true,
            root: true,
            install_works: false,
        },
    ];

    /// The dependencies of `cargo xtask test`'s optional checks: (check, what, package).
    const DEPENDENCIES: [(&str, &str, &str); 3] = [
        (
            "fuzz-osd round",
            "OpenSubdiv 3.5 (libosd-dev)",
            "libosd-dev",
        ),
        (
            "validation layer",
            "the Vulkan validation layer",
            "vulkan-validationlayers",
        ),
        ("window tests (Xvfb)", "Xvfb or the X11 libraries", "xvfb"),
    ];

    /// `package` as `cargo xtask test` asks for it, on `machine` where it is not installed.
    fn missing_on(what: &str, package: &str, machine: &Machine) -> Result<(), String> {
        ensure_optional(what, &[package], &[], machine, &|| false)
    }

    /// libosd-dev as `cargo xtask test` asks for it, on `machine` where it is not installed.
    fn libosd_on(machine: &Machine) -> Result<(), String> {
        missing_on(DEPENDENCIES[0].1, DEPENDENCIES[0].2, machine)
    }

    #[test]
    fn a_missing_dependency_fails_under_ci_on_every_path() {
        for (check, what, package) in DEPENDENCIES {
            for machine in &MISSING {
                let why = missing_on(what, package, machine).expect_err("it is missing");
                assert!(why.contains(package), "{why}");
                let mut checks = Checks::new(true);
                checks.record("cargo tests", Ok(()));
                checks.unavailable(check, &why);
                assert!(matches!(checks.outcome(check), Some(Outcome::Failed(_))));
                assert_eq!(checks.summary(), "xtask: 1 passed, 1 failed, 0 skipped");
                assert!(checks.finish().is_err());
            }
        }
    }

    #[test]
    fn a_missing_dependency_is_a_named_skip_outside_ci() {
        for machine in &MISSING {
            let mut checks = Checks::new(false);
            checks.record("cargo tests", Ok(()));
            checks.unavailable("fuzz-osd round", &libosd_on(machine).unwrap_err());
            checks.unavailable("window tests (Xvfb)", "no xvfb-run");
            assert_eq!(
                checks.summary(),
                "xtask: 1 passed, 0 failed, 2 skipped (fuzz-osd round, window tests (Xvfb))"
            );
            assert!(checks.finish().is_ok());
        }
    }

    #[test]
    fn a_present_or_installed_dependency_runs() {
        let installed = std::cell::Cell::new(false);
        let machine = Machine {
            apt: true,
            root: true,
            install_works: true,
        };
        struct Installs<'a>(&'a Machine, &'a std::cell::Cell<bool>);
        impl Installer for Installs<'_> {
            fn has_apt(&self) -> bool {
                self.0.apt
            }
            fn is_root(&self) -> bool {
                self.0.root
            }
            fn run(&self, _cmd: &str) -> bool {
                self.1.set(true);
                true
            }
        }
        let r = ensure_optional("x", &["x"], &[], &Installs(&machine, &installed), &|| {
            installed.get()
        });
        assert_eq!(r, Ok(()));
        assert_eq!(
            ensure_optional("x", &["x"], &[], &machine, &|| true),
            Ok(())
        );
        // An install that reports success but leaves the dependency missing is a failure.
        let why = ensure_optional("x", &["x"], &[], &machine, &|| false).unwrap_err();
        assert!(why.contains("failed"), "{why}");
    }

    #[test]
    fn a_failed_check_fails_the_run_in_and_out_of_ci() {
        for ci in [false, true] {
            let mut checks = Checks::new(ci);
            checks.record("goldens", Err(anyhow::anyhow!("2 images differ")));
            assert_eq!(checks.summary(), "xtask: 0 passed, 1 failed, 0 skipped");
            assert!(checks.finish().is_err());
        }
    }

    #[test]
    fn ci_is_read_from_the_environment_values_services_set() {
        for (v, ci) in [
            ("true", true),
            ("TRUE", true),
            ("1", true),
            ("false", false),
            ("", false),
            ("0", false),
        ] {
            assert_eq!(ci_value(v), ci, "CI={v}");
        }
    }
}
