//! Opens the viewer on a torus whose geometry is produced per frame.
//!
//! `cargo run -p subdiv-vk --example viewer -- [--screenshot-after N -o FILE.png]`

mod common;

use subdiv_vk::viewer::{self, FrameRequest, FrameSource, SourceFrame, ViewerOptions};
use subdiv_vk::{RenderMesh, Shading};

/// Stands in for the adaptive tessellator: a finer torus while the frame rate
/// is above target, a coarser one below, when frame-rate control is on.
struct Adaptive {
    level: u32,
    torus: Option<common::Torus>,
    scalars: Vec<f32>,
    status: String,
}

impl FrameSource for Adaptive {
    fn frame(
        &mut self,
        request: &FrameRequest,
    ) -> Result<SourceFrame<'_>, Box<dyn std::error::Error + Send + Sync>> {
        let previous = self.level;
        if request.control.is_on() && request.frame_index > 0 {
            let fps = 1.0 / request.last_frame_time.as_secs_f32().max(1e-6);
            if fps > request.target_fps * 1.2 && self.level < 6 {
                self.level += 1;
            } else if fps < request.target_fps * 0.8 && self.level > 0 {
                self.level -= 1;
            }
        }
        let n = 12 << self.level;
        let torus = match self.torus.take() {
            Some(t) if previous == self.level => t,
            _ => common::torus(n, n / 2),
        };
        let torus = self.torus.insert(torus);
        if request.shading == Shading::Doi {
            // A smooth "interest" value: height above the torus plane.
            self.scalars = torus.positions.iter().map(|p| p[1]).collect();
        } else if request.shading == Shading::Depth {
            self.scalars = vec![self.level as f32; torus.positions.len()];
        } else {
            self.scalars.clone_from(&torus.scalars);
        }
        self.status = format!("level {}", self.level);
        Ok(SourceFrame {
            mesh: RenderMesh {
                scalars: Some(&self.scalars),
                ..torus.render_mesh()
            },
            status: &self.status,
            vertex_version: None,
            dirty_vertices: None,
            depth_cap: Some(self.level),
            predicted_ms: None,
        })
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut options = ViewerOptions {
        title: "subdiv-vk viewer example".into(),
        ..Default::default()
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--screenshot-after" => {
                options.screenshot_after = args.next().map(|n| n.parse()).transpose()?
            }
            "-o" => options.screenshot_path = args.next().ok_or("-o needs a path")?.into(),
            "--size" => {
                let s = args.next().ok_or("--size needs WxH")?;
                let (w, h) = s.split_once('x').ok_or("--size needs WxH")?;
                options.size = [w.parse()?, h.parse()?];
            }
            other => return Err(format!("unknown argument {other}").into()),
        }
    }
    let mut source = Adaptive {
        level: 2,
        torus: None,
        scalars: Vec::new(),
        status: String::new(),
    };
    let report = viewer::run(&mut source, options)?;
    println!(
        "{} frames, screenshots: {:?}",
        report.frames, report.screenshots
    );
    Ok(())
}
