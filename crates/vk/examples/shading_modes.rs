//! Renders a torus in every shading mode to PNG (and one EXR).
//!
//! `cargo run -p subdiv-vk --example shading_modes -- OUT_DIR`

mod common;

use subdiv_vk::{OrbitCamera, RenderOptions, Renderer, Shading};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "out/vk".into()));
    let t = common::torus(48, 24);
    let mesh = t.render_mesh();
    let size = [480, 360];
    let view = OrbitCamera::framing_mesh(&mesh).view(size[0] as f32 / size[1] as f32);
    let mut renderer = Renderer::new()?;
    println!("device: {}", renderer.device_name());
    for (shading, name) in Shading::ALL {
        let options = RenderOptions {
            shading,
            show_lines: false,
            ..Default::default()
        };
        let start = std::time::Instant::now();
        let image = renderer.render(&mesh, &view, size, &options)?;
        println!("{name}: {:?}", start.elapsed());
        subdiv_vk::write_png(out.join(format!("{name}.png")), &image)?;
    }
    let options = RenderOptions {
        shading: Shading::Depth,
        wire_overlay: true,
        ..Default::default()
    };
    let (image, aux) = renderer.render_with_aux(&mesh, &view, size, &options)?;
    subdiv_vk::write_png(out.join("depth-wire-lines.png"), &image)?;
    subdiv_vk::write_exr(out.join("depth-wire-lines.exr"), &aux)?;
    Ok(())
}
