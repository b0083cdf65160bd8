//! Renders a torus in every shading mode to PNG (and one EXR).
//!
//! `cargo run -p subdiv-vk --example shading_modes -- OUT_DIR`

use std::f32::consts::TAU;

use subdiv_vk::{OrbitCamera, RenderMesh, RenderOptions, Renderer, Shading};

/// A torus with quad edges (no diagonals), a per-quad "depth" and a smooth scalar.
struct Torus {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    triangles: Vec<u32>,
    edges: Vec<[u32; 2]>,
    scalars: Vec<f32>,
    silhouette: Vec<[f32; 3]>,
}

fn torus(segments: u32, rings: u32) -> Torus {
    let (big, small) = (1.0f32, 0.4f32);
    let mut t = Torus {
        positions: vec![],
        normals: vec![],
        triangles: vec![],
        edges: vec![],
        scalars: vec![],
        silhouette: vec![],
    };
    // Vertices are duplicated per quad so each quad carries its own depth value.
    for i in 0..segments {
        for j in 0..rings {
            let base = t.positions.len() as u32;
            let depth = ((i / 4 + j / 3) % 5) as f32;
            for (di, dj) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                let u = (i + di) as f32 / segments as f32 * TAU;
                let v = (j + dj) as f32 / rings as f32 * TAU;
                let n = [v.cos() * u.cos(), v.sin(), v.cos() * u.sin()];
                let p = [
                    (big + small * v.cos()) * u.cos(),
                    small * v.sin(),
                    (big + small * v.cos()) * u.sin(),
                ];
                t.positions.push(p);
                t.normals.push(n);
                t.scalars.push(depth);
            }
            t.triangles
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            t.edges.extend([
                [base, base + 1],
                [base + 1, base + 2],
                [base + 2, base + 3],
                [base + 3, base],
            ]);
        }
    }
    // The outer equator as a stand-in silhouette polyline.
    for i in 0..64 {
        for k in [i, i + 1] {
            let u = k as f32 / 64.0 * TAU;
            t.silhouette
                .push([(big + small) * u.cos(), 0.0, (big + small) * u.sin()]);
        }
    }
    t
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "out/vk".into()));
    let t = torus(48, 24);
    let mesh = RenderMesh {
        positions: &t.positions,
        normals: &t.normals,
        triangles: &t.triangles,
        edges: Some(&t.edges),
        scalars: Some(&t.scalars),
        lines: Some(&t.silhouette),
    };
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
