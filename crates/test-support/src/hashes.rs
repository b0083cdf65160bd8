//! Recorded output hashes: a 64-bit FNV-1a over the output's bits ([`Fnv`]), the platform's
//! `sin`/`cos` fingerprint the bits depend on ([`trig_fingerprint`]), and the comparison of a
//! test's hash lines with the file that records them ([`check_recorded`]).
//!
//! Bits depend on IEEE `f32`/`f64` arithmetic (Rust never contracts to FMA) and on the
//! platform's `sin`/`cos`, which the limit masks of extraordinary vertices use; a recording
//! starts with a fingerprint of those, and on a platform whose fingerprint differs only what the
//! caller asserted itself (thread-count and reuse independence) is checked, and the test says so.

use std::path::Path;

/// 64-bit FNV-1a over bytes.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(pub u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv::new()
    }
}

impl Fnv {
    /// The empty hash.
    pub fn new() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    /// Hashes bytes.
    pub fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    /// Hashes a `u32` (little-endian bytes).
    pub fn u32(&mut self, x: u32) {
        self.bytes(&x.to_le_bytes());
    }
    /// Hashes `u32`s.
    pub fn u32s(&mut self, v: &[u32]) {
        for &x in v {
            self.u32(x);
        }
    }
    /// Hashes the bits of `f32`s.
    pub fn f32s(&mut self, v: &[f32]) {
        for &x in v {
            self.u32(x.to_bits());
        }
    }
}

/// The platform's `sin` and `cos` at the angles the limit masks use (`2 pi i / n`).
pub fn trig_fingerprint() -> u64 {
    let mut h = Fnv::new();
    for n in 3..=64u32 {
        let th = 2.0 * std::f64::consts::PI / n as f64;
        for i in 0..=n {
            let (s, c) = (th * i as f64).sin_cos();
            h.bytes(&s.to_bits().to_le_bytes());
            h.bytes(&c.to_bits().to_le_bytes());
        }
        let x = 1.0 + th.cos() + (th * 0.5).cos() * (2.0 * (9.0 + th.cos())).sqrt();
        h.bytes(&x.to_bits().to_le_bytes());
    }
    h.0
}

/// Compares `now` (one line per case) with the file `path`: its first line is the platform's
/// sin/cos fingerprint (on another platform nothing more is compared, and the test says so on
/// stderr); with the environment variable `bless_env` set the file is rewritten instead.
/// Panics naming every changed line.
pub fn check_recorded(path: &Path, now: &str, bless_env: &str) {
    let file = path.display();
    let fingerprint = format!("trig {:016x}\n", trig_fingerprint());
    if std::env::var_os(bless_env).is_some() {
        std::fs::write(path, format!("{fingerprint}{now}"))
            .unwrap_or_else(|e| panic!("write {file}: {e}"));
        return;
    }
    let recorded = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("read {file}: {e}"));
    let (head, cases) = recorded.split_at(recorded.find('\n').map_or(0, |i| i + 1));
    if head != fingerprint {
        eprintln!(
            "{file}: this platform's sin/cos differ from the recording's ({} vs {}): only \
             thread-count and reuse independence were checked",
            fingerprint.trim(),
            head.trim()
        );
        return;
    }
    let bad: Vec<String> = cases
        .lines()
        .zip(now.lines())
        .filter(|(want, got)| want != got)
        .map(|(want, got)| format!("recorded {want}\n     now {got}"))
        .collect();
    assert_eq!(
        cases.lines().count(),
        now.lines().count(),
        "{file}: case count"
    );
    assert!(
        bad.is_empty(),
        "{file}: output changed:\n{}",
        bad.join("\n")
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv_matches_the_reference_values() {
        // FNV-1a 64 of "" and "a" (the algorithm's published test vectors).
        assert_eq!(Fnv::new().0, 0xcbf2_9ce4_8422_2325);
        let mut h = Fnv::new();
        h.bytes(b"a");
        assert_eq!(h.0, 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn a_changed_line_is_reported() {
        let dir = std::env::temp_dir().join(format!("subdiv-hashes-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("h.txt");
        let fp = format!("trig {:016x}\n", trig_fingerprint());
        std::fs::write(&path, format!("{fp}a 1\nb 2\n")).unwrap();
        check_recorded(&path, "a 1\nb 2\n", "SUBDIV_TEST_SUPPORT_NEVER_SET");
        let changed = std::panic::catch_unwind(|| {
            check_recorded(&path, "a 1\nb 3\n", "SUBDIV_TEST_SUPPORT_NEVER_SET")
        });
        assert!(changed.is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
