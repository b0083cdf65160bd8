//! The viewer's input decisions, kept apart from the event loop so they can be tested: what a
//! mouse drag does, and when frames are drawn back to back.

/// What a mouse drag does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Drag {
    /// Turn about the camera's up axis and tilt (left button).
    Orbit,
    /// Move the target with the cursor (middle button, or shift + left button).
    Pan,
}

/// The drag for the buttons held and the shift key; `None` without a button.
pub(super) fn drag(left: bool, middle: bool, shift: bool) -> Option<Drag> {
    if middle || (left && shift) {
        Some(Drag::Pan)
    } else if left {
        Some(Drag::Orbit)
    } else {
        None
    }
}

/// Whether the viewer draws frames back to back: with frame-rate control on (the controller
/// needs real frame times), or while a scripted screenshot after `screenshot_after` frames is
/// still to come; otherwise it waits for events and draws only on changes.
pub(super) fn draws_continuously(
    frame_rate_control: bool,
    screenshot_after: Option<u32>,
    frames: u64,
) -> bool {
    frame_rate_control || screenshot_after.is_some_and(|n| frames < u64::from(n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drags_orbit_or_pan() {
        assert_eq!(drag(true, false, false), Some(Drag::Orbit));
        assert_eq!(drag(true, false, true), Some(Drag::Pan));
        assert_eq!(drag(false, true, false), Some(Drag::Pan));
        assert_eq!(drag(false, true, true), Some(Drag::Pan));
        assert_eq!(drag(false, false, true), None);
    }

    #[test]
    fn idle_without_frame_rate_control() {
        assert!(!draws_continuously(false, None, 0));
        assert!(!draws_continuously(false, None, 1000));
        assert!(draws_continuously(true, None, 1000));
        assert!(draws_continuously(false, Some(3), 2));
        assert!(!draws_continuously(false, Some(3), 3));
    }
}
