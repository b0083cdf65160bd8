//! Grids of quads the versioned-render tests draw: flat, or with rows lifted.

use subdiv_vk::glam::Vec3;

/// Positions, normals and triangle indices.
pub type Grid = (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>);

/// A `k × k` grid of quads in the z = 0 plane, vertices lifted by `bump(i, j)` along z, with
/// normals tilted by the lift so the shading shows it.
pub fn grid(k: u32, bump: impl Fn(u32, u32) -> f32) -> Grid {
    let mut pos = Vec::new();
    let mut nrm = Vec::new();
    for j in 0..=k {
        for i in 0..=k {
            let z = bump(i, j);
            pos.push([
                i as f32 / k as f32 * 2.0 - 1.0,
                j as f32 / k as f32 * 2.0 - 1.0,
                z,
            ]);
            nrm.push(Vec3::new(z, 0.5 * z, 1.0).normalize().to_array());
        }
    }
    let mut tris = Vec::new();
    let w = k + 1;
    for j in 0..k {
        for i in 0..k {
            let a = j * w + i;
            tris.extend_from_slice(&[a, a + 1, a + w + 1, a, a + w + 1, a + w]);
        }
    }
    (pos, nrm, tris)
}
