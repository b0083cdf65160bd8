//! The crate boundary around the `openusd` reader: a panic inside it becomes a
//! [`UsdError::ReaderPanic`] naming the file and what was being read, and the default panic
//! message is not printed (the caller sees the one error).
//!
//! The panic hook is process-wide, so it is replaced once, by a hook that keeps the message of a
//! panic raised on a thread inside [`catch_reader`] and hands every other panic to the hook it
//! replaced. A hook installed later by the application takes over; panics are still caught, only
//! their message is then printed by that hook as well.

use std::cell::{Cell, RefCell};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

use crate::error::UsdError;

thread_local! {
    /// How many [`catch_reader`] calls this thread is inside.
    static DEPTH: Cell<u32> = const { Cell::new(0) };
    /// The first panic message (with its location) raised inside them.
    static MESSAGE: RefCell<Option<String>> = const { RefCell::new(None) };
}

static HOOK: Once = Once::new();

fn install_hook() {
    HOOK.call_once(|| {
        let prev = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if DEPTH.with(Cell::get) == 0 {
                return prev(info);
            }
            let msg = payload_text(info.payload());
            let text = match info.location() {
                Some(l) => format!("{msg} (at {}:{})", short_path(l.file()), l.line()),
                None => msg,
            };
            MESSAGE.with(|m| {
                m.borrow_mut().get_or_insert(text);
            });
        }));
    });
}

/// The message of a panic payload (`panic!` with a literal or a formatted string).
fn payload_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".to_string())
}

/// A source path from the crate's name on (`openusd-0.6.0/src/usdc/reader.rs` from the
/// registry, `openusd/src/usdc/reader.rs` vendored), without the directories in front of it.
fn short_path(file: &str) -> &str {
    match file.rfind("openusd") {
        Some(i) => &file[i..],
        None => file,
    }
}

/// What the reader is doing, updated as the read goes on (named in a [`UsdError::ReaderPanic`]).
pub(crate) struct Doing(RefCell<String>);

impl Doing {
    /// Records what the reader starts doing now.
    pub(crate) fn set(&self, what: impl Into<String>) {
        *self.0.borrow_mut() = what.into();
    }
}

/// Runs `f`, which calls into the `openusd` reader; a panic becomes a
/// [`UsdError::ReaderPanic`] for `file`, naming what [`Doing`] said last.
pub(crate) fn catch_reader<T>(
    file: &str,
    f: impl FnOnce(&Doing) -> Result<T, UsdError>,
) -> Result<T, UsdError> {
    install_hook();
    let doing = Doing(RefCell::new("opening the stage".to_string()));
    DEPTH.with(|d| d.set(d.get() + 1));
    let r = catch_unwind(AssertUnwindSafe(|| f(&doing)));
    DEPTH.with(|d| d.set(d.get() - 1));
    let kept = MESSAGE.with(|m| m.borrow_mut().take());
    r.unwrap_or_else(|payload| {
        Err(UsdError::ReaderPanic {
            path: file.to_string(),
            doing: doing.0.into_inner(),
            msg: kept.unwrap_or_else(|| payload_text(payload.as_ref())),
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_a_typed_error_naming_the_file_and_the_step() {
        let r: Result<(), UsdError> = catch_reader("bad.usdc", |doing| {
            doing.set("reading prim /World/Mesh");
            let v: Vec<u32> = Vec::new();
            let i = v.len() + 3;
            panic!("index {i} out of range");
        });
        let e = r.unwrap_err();
        assert!(matches!(e, UsdError::ReaderPanic { .. }), "{e:?}");
        let msg = e.to_string();
        assert!(
            msg.starts_with("bad.usdc: the USD reader failed while reading prim /World/Mesh: "),
            "{msg}"
        );
        assert!(msg.contains("index 3 out of range"), "{msg}");
        assert!(msg.contains("catch.rs:"), "the location is named: {msg}");
        // The thread is usable afterwards, and results and errors pass through unchanged.
        assert_eq!(catch_reader("ok.usda", |_| Ok(7)).unwrap(), 7);
        let e = catch_reader::<()>("x.usda", |_| {
            Err(UsdError::NoMesh {
                path: "x.usda".into(),
            })
        });
        assert!(matches!(e, Err(UsdError::NoMesh { .. })));
    }

    #[test]
    fn a_nested_catch_reports_the_inner_panic_once() {
        let r = catch_reader("outer.usda", |_| {
            catch_reader::<()>("inner.usda", |_| panic!("inner"))
        });
        let e = r.unwrap_err().to_string();
        assert!(e.starts_with("inner.usda: "), "{e}");
        assert!(e.contains("inner (at "), "{e}");
    }
}
