//! Standard output that ends quietly when the reader goes away.
//!
//! `println!` panics when stdout is a closed pipe (`subdiv refine ... | head -1`). Every report
//! line of the command goes through [`out!`] instead: a closed pipe ends the process with status 0
//! (the reader has what it wanted, as `ripgrep` does), any other write error ends it with a
//! message and status 1. Progress bars and logs go to stderr and are not affected.

use std::io::{ErrorKind, Write};

/// Writes one line to stdout like `println!`, without panicking on a closed pipe.
macro_rules! out {
    () => {
        $crate::out::line(format_args!(""))
    };
    ($($arg:tt)*) => {
        $crate::out::line(format_args!($($arg)*))
    };
}

/// Writes `args` and a newline to stdout; see the module documentation for errors.
pub fn line(args: std::fmt::Arguments<'_>) {
    write(args, b"\n");
}

/// Writes `text` to stdout as it is (no newline added); errors as [`line`].
pub fn text(text: &str) {
    write(format_args!("{text}"), b"");
}

fn write(args: std::fmt::Arguments<'_>, end: &[u8]) {
    let mut stdout = std::io::stdout().lock();
    let written = stdout
        .write_fmt(args)
        .and_then(|()| stdout.write_all(end))
        .and_then(|()| stdout.flush());
    if let Err(e) = written {
        if e.kind() == ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: writing to standard output: {e}");
        std::process::exit(1);
    }
}
