//! The viewer writes only the vertices a source marks dirty, into each frame in flight, from
//! the versions since the one that frame last drew (`SourceFrame::dirty_vertices`): blocks
//! appended version after version are drawn, and a vertex rewritten without being marked
//! keeps what the viewer already held, which shows that the rest was not written.
//!
//! winit allows one event loop per process, so this file holds one test. Without `DISPLAY`
//! (or without a Vulkan driver) it prints a note and passes, unless
//! `SUBDIV_VK_REQUIRE_DISPLAY=1` is set.

mod common;
mod grid;

use std::ops::Range;

use grid::{Grid, grid};
use subdiv_vk::glam::Vec3;
use subdiv_vk::viewer::{FrameRequest, FrameSource, SourceFrame};
use subdiv_vk::{OrbitCamera, RenderMesh, RenderOptions};

/// Grid side in quads.
const K: u32 = 6;
/// The last version; frames from `LAST - 1` on show it.
const LAST: u64 = 8;

/// Version `k` (1..=[`LAST`]): the flat grid at the origin, then `k - 1` lifted grids
/// beside it, appended one per version; the origin's grid and the newest are drawn. The last
/// version also lifts the origin's grid without marking it dirty.
struct Growing {
    flat: Grid,
    lifted: Grid,
    frame: Grid,
    dirty: Vec<Range<u32>>,
}

impl Growing {
    fn new() -> Growing {
        Growing {
            flat: grid(K, |_, _| 0.0),
            lifted: grid(K, |_, j| if (2..=3).contains(&j) { 0.4 } else { 0.0 }),
            frame: Default::default(),
            dirty: Vec::new(),
        }
    }

    /// Version `k`'s vertices, drawn triangles and dirty ranges into `self`.
    fn build(&mut self, k: u64) {
        let n = self.flat.0.len() as u32;
        let shifted = |p: &[f32; 3]| [p[0] + 2.5, p[1], p[2]];
        let first = if k == LAST { &self.lifted } else { &self.flat };
        let (pos, nrm, tris) = &mut self.frame;
        pos.clear();
        nrm.clear();
        pos.extend_from_slice(&first.0);
        nrm.extend_from_slice(&first.1);
        for _ in 1..k {
            pos.extend(self.lifted.0.iter().map(shifted));
            nrm.extend_from_slice(&self.lifted.1);
        }
        tris.clear();
        tris.extend_from_slice(&self.flat.2);
        let newest = (k as u32 - 1) * n;
        tris.extend(self.flat.2.iter().map(|&i| i + newest));
        self.dirty.clear();
        if k > 1 {
            self.dirty.push(newest..newest + n);
        }
    }
}

impl FrameSource for Growing {
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        let version = (request.frame_index + 1).min(LAST);
        self.build(version);
        let (pos, nrm, tris) = &self.frame;
        Ok(SourceFrame {
            mesh: RenderMesh {
                positions: pos,
                normals: nrm,
                triangles: tris,
                ..Default::default()
            },
            status: "",
            vertex_version: Some(version),
            dirty_vertices: Some(&self.dirty),
            depth_cap: None,
            predicted_ms: None,
        })
    }
}

#[test]
fn appended_blocks_are_written_and_the_rest_is_kept() {
    let Some(mut headless) = common::display_and_renderer() else {
        return;
    };
    let camera = OrbitCamera::framing(Vec3::new(-1.0, -1.0, -0.5), Vec3::new(3.5, 1.0, 0.5));
    let render = RenderOptions::default();
    let mut source = Growing::new();
    let frames = LAST as u32 + 3;
    let (report, shot) = common::viewer_screenshot(&mut source, camera, render, frames, "versions");
    assert_eq!(report.frames, u64::from(frames));
    // What the viewer holds: the origin's grid flat (its lift was not marked dirty), the
    // newest block lifted beside it.
    let mut held = Growing::new();
    held.build(LAST);
    let n = held.flat.0.len();
    held.frame.0[..n].copy_from_slice(&held.flat.0);
    held.frame.1[..n].copy_from_slice(&held.flat.1);
    let view = camera.view(160.0 / 120.0);
    let mut mesh = |g: &Grid| {
        let (pos, nrm, tris) = g;
        headless
            .render(
                &RenderMesh {
                    positions: pos,
                    normals: nrm,
                    triangles: tris,
                    ..Default::default()
                },
                &view,
                [160, 120],
                &render,
            )
            .unwrap()
    };
    let expected = mesh(&held.frame);
    let mut source_last = Growing::new();
    source_last.build(LAST);
    let written_in_full = mesh(&source_last.frame);
    assert!(written_in_full != expected, "the unmarked lift must show");
    assert!(
        shot == expected,
        "the viewer's frame is not the appended blocks over the vertices it held"
    );
}
