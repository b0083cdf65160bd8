//! Playback of an animated source: the time code each frame is asked for
//! ([`super::FrameRequest::time`]), whole time codes at the source's rate while playing,
//! looping over the range; space pauses and plays, the arrow keys step one time code.

use std::time::Instant;

/// An animated source's time range and where the viewer starts in it
/// ([`super::ViewerOptions::playback`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Playback {
    /// First time code of the range.
    pub start: f64,
    /// Last time code of the range (at least `start`).
    pub end: f64,
    /// Time codes per second (a USD stage's `timeCodesPerSecond`).
    pub rate: f64,
    /// The time code of the first frame.
    pub time: f64,
    /// Whether playback starts running (else paused at `time`).
    pub playing: bool,
}

/// A key of the playback controls (also what tests inject, [`super::Fault::Press`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlaybackKey {
    /// Space: pause or play.
    PlayPause,
    /// Left arrow: one time code back (pauses).
    StepBack,
    /// Right arrow: one time code on (pauses).
    StepForward,
}

/// The playback state of a viewer session.
#[derive(Clone, Debug)]
pub(super) struct Player {
    start: f64,
    end: f64,
    rate: f64,
    /// The time code shown while paused, and where playback resumed.
    time: f64,
    /// While playing: when playback (re)started.
    since: Option<Instant>,
}

impl Player {
    pub(super) fn new(p: Playback, now: Instant) -> Player {
        let end = if p.end >= p.start { p.end } else { p.start };
        let rate = if p.rate.is_finite() && p.rate > 0.0 {
            p.rate
        } else {
            24.0
        };
        let mut player = Player {
            start: p.start,
            end,
            rate,
            time: p.start,
            since: p.playing.then_some(now),
        };
        player.time = player.wrap(p.time);
        player
    }

    /// Whether playback runs (frames are then drawn back to back).
    pub(super) fn playing(&self) -> bool {
        self.since.is_some()
    }

    /// `t` moved into the range: time codes past the end continue from the start, and before
    /// the start from the end, a whole number of range lengths (`end - start + 1` codes) away.
    fn wrap(&self, t: f64) -> f64 {
        let len = (self.end - self.start).floor() + 1.0;
        if !t.is_finite() {
            return self.start;
        }
        if t > self.end || t < self.start {
            self.start + (t - self.start).rem_euclid(len)
        } else {
            t
        }
    }

    /// The time code of a frame drawn at `now`: while playing, the time playback started at
    /// plus the whole time codes elapsed since at [`Playback::rate`], looping over the range.
    pub(super) fn time_at(&self, now: Instant) -> f64 {
        match self.since {
            Some(since) => {
                let codes = (now.duration_since(since).as_secs_f64() * self.rate).floor();
                self.wrap(self.time + codes)
            }
            None => self.time,
        }
    }

    /// Applies a playback key pressed at `now`.
    pub(super) fn press(&mut self, key: PlaybackKey, now: Instant) {
        let shown = self.time_at(now);
        match key {
            PlaybackKey::PlayPause => {
                self.time = shown;
                self.since = if self.playing() { None } else { Some(now) };
            }
            PlaybackKey::StepBack | PlaybackKey::StepForward => {
                let step = if key == PlaybackKey::StepBack {
                    -1.0
                } else {
                    1.0
                };
                self.time = self.wrap(shown + step);
                self.since = None;
            }
        }
    }

    /// For the window title: `time T (start-end, playing)`.
    pub(super) fn status(&self, now: Instant) -> String {
        let state = if self.playing() { "playing" } else { "paused" };
        format!(
            "time {} ({}-{}, {state})",
            self.time_at(now),
            self.start,
            self.end
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn player(time: f64, playing: bool, now: Instant) -> Player {
        Player::new(
            Playback {
                start: 1.0,
                end: 48.0,
                rate: 24.0,
                time,
                playing,
            },
            now,
        )
    }

    #[test]
    fn plays_whole_time_codes_at_the_rate_and_loops() {
        let t0 = Instant::now();
        let p = player(1.0, true, t0);
        assert_eq!(p.time_at(t0), 1.0);
        assert_eq!(p.time_at(t0 + Duration::from_millis(1000)), 25.0);
        assert_eq!(p.time_at(t0 + Duration::from_millis(1010)), 25.0);
        // 48 codes later: the start again.
        assert_eq!(p.time_at(t0 + Duration::from_millis(2000)), 1.0);
        assert_eq!(p.time_at(t0 + Duration::from_millis(2000 + 42 * 47)), 48.0);
        let paused = player(13.0, false, t0);
        assert_eq!(paused.time_at(t0 + Duration::from_secs(5)), 13.0);
    }

    #[test]
    fn keys_pause_play_and_step() {
        let t0 = Instant::now();
        let mut p = player(47.0, false, t0);
        p.press(PlaybackKey::StepForward, t0);
        assert_eq!(p.time_at(t0), 48.0);
        p.press(PlaybackKey::StepForward, t0);
        assert_eq!(p.time_at(t0), 1.0);
        p.press(PlaybackKey::StepBack, t0);
        assert_eq!(p.time_at(t0), 48.0);
        p.press(PlaybackKey::PlayPause, t0);
        assert!(p.playing());
        let t1 = t0 + Duration::from_millis(500);
        assert_eq!(p.time_at(t1), 12.0);
        // Pausing keeps the time shown; stepping pauses.
        p.press(PlaybackKey::PlayPause, t1);
        assert!(!p.playing());
        assert_eq!(p.time_at(t1 + Duration::from_secs(3)), 12.0);
        p.press(PlaybackKey::PlayPause, t1);
        p.press(PlaybackKey::StepBack, t1 + Duration::from_millis(100));
        assert!(!p.playing());
        assert_eq!(p.time_at(t1 + Duration::from_secs(1)), 13.0);
        assert_eq!(p.status(t1), "time 13 (1-48, paused)");
    }

    #[test]
    fn a_start_time_outside_the_range_is_wrapped_into_it() {
        let t0 = Instant::now();
        assert_eq!(player(50.0, false, t0).time_at(t0), 2.0);
        assert_eq!(player(0.0, false, t0).time_at(t0), 48.0);
        assert_eq!(player(12.5, false, t0).time_at(t0), 12.5);
    }
}
