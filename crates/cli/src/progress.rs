//! Progress bars for work that takes more than about a second (deep tessellation and
//! refinement, benchmarks, quality runs), drawn with `indicatif` on stderr.
//!
//! Bars are drawn only when stderr is a terminal and `-q` is off: piped or redirected output
//! is byte-identical to a run without bars. All bars live in one `MultiProgress`, which the
//! logger suspends while it writes a line.

use std::borrow::Cow;
use std::sync::OnceLock;
use std::time::Duration;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

static BARS: OnceLock<MultiProgress> = OnceLock::new();

/// Sets up the bars: drawn on a terminal stderr unless `quiet`, hidden otherwise. Call once
/// at start; without it bars are hidden.
pub fn init(quiet: bool) {
    let target = if quiet {
        ProgressDrawTarget::hidden()
    } else {
        // `stderr()` draws nothing when stderr is not a terminal.
        ProgressDrawTarget::stderr()
    };
    let _ = BARS.set(MultiProgress::with_draw_target(target));
}

fn bars() -> &'static MultiProgress {
    BARS.get_or_init(|| MultiProgress::with_draw_target(ProgressDrawTarget::hidden()))
}

/// Runs `f` with the bars cleared from the terminal (for printing a line).
pub fn suspend<R>(f: impl FnOnce() -> R) -> R {
    bars().suspend(f)
}

/// A bar of `len` steps labelled `what`; finish it with [`ProgressBar::finish_and_clear`].
pub fn bar(len: u64, what: impl Into<Cow<'static, str>>) -> ProgressBar {
    let style = ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} {elapsed} (eta {eta})")
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
    let bar = bars().add(ProgressBar::new(len).with_style(style));
    bar.set_message(what);
    bar
}

/// A spinner with elapsed time for one long call labelled `what`; it ticks on its own until
/// finished ([`ProgressBar::finish_and_clear`]).
pub fn spinner(what: impl Into<Cow<'static, str>>) -> ProgressBar {
    let style = ProgressStyle::with_template("{spinner} {msg} {elapsed}")
        .unwrap_or_else(|_| ProgressStyle::default_spinner());
    let bar = bars().add(ProgressBar::new_spinner().with_style(style));
    bar.set_message(what);
    bar.enable_steady_tick(Duration::from_millis(120));
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_are_hidden_off_a_terminal() {
        use std::io::IsTerminal;
        init(false);
        let piped = !std::io::stderr().is_terminal();
        let b = bar(3, "work");
        b.inc(1);
        assert_eq!(b.is_hidden(), piped);
        let s = spinner("long call");
        assert_eq!(s.is_hidden(), piped);
        s.finish_and_clear();
        b.finish_and_clear();
    }
}
