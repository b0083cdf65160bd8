//! Playback under X11 (`xvfb-run -a`): the time code each frame is asked for, with the space
//! and arrow keys pressed through the viewer's own key handling ([`Fault::Press`]).
//!
//! winit allows one event loop per process, so this file holds one test. Without `DISPLAY`
//! (or without a Vulkan driver) it prints a note and passes, unless
//! `SUBDIV_VK_REQUIRE_DISPLAY=1` is set.

mod octahedron;

use octahedron::{POSITIONS, SCALARS, TRIANGLES};
use subdiv_vk::glam::Vec3;
use subdiv_vk::viewer::{
    self, Fault, FrameRequest, FrameSource, Playback, PlaybackKey, SourceFrame, ViewerOptions,
};
use subdiv_vk::{ContextOptions, OrbitCamera, RenderMesh, Validation, VkError};

/// Records the time code of every frame asked for.
struct Timed {
    times: Vec<Option<f64>>,
}

impl FrameSource for Timed {
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        self.times.push(request.time);
        Ok(SourceFrame {
            mesh: RenderMesh {
                positions: &POSITIONS,
                normals: &POSITIONS,
                triangles: &TRIANGLES,
                scalars: Some(&SCALARS),
                ..Default::default()
            },
            status: "",
            vertex_version: None,
            dirty_vertices: None,
            depth_cap: None,
            predicted_ms: None,
        })
    }
}

#[test]
fn keys_step_pause_and_play_the_time_codes() {
    let require = std::env::var("SUBDIV_VK_REQUIRE_DISPLAY").as_deref() == Ok("1");
    if std::env::var_os("DISPLAY").is_none() && !require {
        eprintln!("skipping: no DISPLAY (run under xvfb-run)");
        return;
    }
    let dir = std::env::temp_dir().join(format!("subdiv-vk-playback-{}", std::process::id()));
    let press = |frame: u64, key| (frame, Fault::Press(key));
    let mut source = Timed { times: Vec::new() };
    let report = viewer::run(
        &mut source,
        ViewerOptions {
            size: [160, 120],
            camera: Some(OrbitCamera::framing(Vec3::splat(-1.0), Vec3::splat(1.0))),
            control: subdiv_vk::viewer::FrameControl::Off,
            screenshot_after: Some(10),
            screenshot_path: dir.join("shot.png"),
            hud: false,
            playback: Some(Playback {
                start: 1.0,
                end: 4.0,
                rate: 1000.0,
                time: 2.0,
                playing: false,
            }),
            faults: vec![
                press(2, PlaybackKey::StepForward),
                press(3, PlaybackKey::StepForward),
                press(4, PlaybackKey::StepForward),
                press(5, PlaybackKey::StepBack),
                press(6, PlaybackKey::PlayPause),
            ],
            context: ContextOptions {
                validation: Validation::IfAvailable,
                ..Default::default()
            },
            ..Default::default()
        },
    );
    let report = match report {
        Err(VkError::NoDriver { .. } | VkError::LoaderMissing { .. }) if !require => {
            eprintln!("skipping: no Vulkan driver");
            return;
        }
        r => r.unwrap(),
    };
    assert_eq!(report.frames, 10);
    let t = &source.times;
    assert_eq!(t.len(), 10);
    // Paused at 2; each arrow steps one time code (past the end: the start), pausing.
    assert_eq!(
        t[..6],
        [
            Some(2.0),
            Some(2.0),
            Some(3.0),
            Some(4.0),
            Some(1.0),
            Some(4.0)
        ]
    );
    // Playing from 4 at 1000 codes a second: whole codes of the range, frames back to back.
    for x in &t[6..] {
        let x = x.unwrap();
        assert!((1.0..=4.0).contains(&x) && x.fract() == 0.0, "{t:?}");
    }
    assert!(report.validation_messages.is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}
