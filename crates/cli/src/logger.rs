//! The command's logger: the library crates log through the `log` crate and never print; this
//! prints their records on stderr at the level the global `-q` / `-v` flags choose.
//!
//! Lines read `error: ...`, `warning: ...`, plain text for information, and `debug: TARGET:
//! ...` / `trace: TARGET: ...` with the module that logged them. Progress bars are suspended
//! while a line is written, so the two never interleave.

use log::{Level, LevelFilter, Log, Metadata, Record};

/// The level for `-q` and the count of `-v`: `-q` errors only (no warnings, no progress),
/// default information and warnings, `-v` debug lines, `-vv` and more trace lines.
pub fn level(verbose: u8, quiet: bool) -> LevelFilter {
    match (quiet, verbose) {
        (true, _) => LevelFilter::Error,
        (false, 0) => LevelFilter::Info,
        (false, 1) => LevelFilter::Debug,
        (false, _) => LevelFilter::Trace,
    }
}

/// The text of one record as printed.
fn line(record: &Record<'_>) -> String {
    match record.level() {
        Level::Error => format!("error: {}", record.args()),
        Level::Warn => format!("warning: {}", record.args()),
        Level::Info => format!("{}", record.args()),
        Level::Debug => format!("debug: {}: {}", record.target(), record.args()),
        Level::Trace => format!("trace: {}: {}", record.target(), record.args()),
    }
}

struct StderrLogger;

static LOGGER: StderrLogger = StderrLogger;

impl Log for StderrLogger {
    fn enabled(&self, metadata: &Metadata<'_>) -> bool {
        metadata.level() <= log::max_level()
    }

    fn log(&self, record: &Record<'_>) {
        if self.enabled(record.metadata()) {
            let text = line(record);
            crate::progress::suspend(|| eprintln!("{text}"));
        }
    }

    fn flush(&self) {}
}

/// Installs the logger with the level of `-v` / `-q` (once, at start).
pub fn init(verbose: u8, quiet: bool) {
    // Fails only if a logger is already installed; then that one stays.
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(level(verbose, quiet));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_map_to_levels() {
        assert_eq!(level(0, true), LevelFilter::Error);
        assert_eq!(level(3, true), LevelFilter::Error);
        assert_eq!(level(0, false), LevelFilter::Info);
        assert_eq!(level(1, false), LevelFilter::Debug);
        assert_eq!(level(2, false), LevelFilter::Trace);
    }

    #[test]
    fn lines_name_their_level() {
        let args = format_args!("x.obj:3: tag ignored");
        let warn = Record::builder()
            .level(Level::Warn)
            .args(args)
            .target("subdiv_cli::load")
            .build();
        assert_eq!(line(&warn), "warning: x.obj:3: tag ignored");
        let args = format_args!("device llvmpipe");
        let debug = Record::builder()
            .level(Level::Debug)
            .args(args)
            .target("subdiv_vk::context")
            .build();
        assert_eq!(line(&debug), "debug: subdiv_vk::context: device llvmpipe");
    }
}
