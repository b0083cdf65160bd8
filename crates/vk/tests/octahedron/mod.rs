//! The octahedron the viewer tests draw.

/// The octahedron's vertices (also its normals).
pub static POSITIONS: [[f32; 3]; 6] = [
    [1.0, 0.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.0, 0.0, -1.0],
];
pub static TRIANGLES: [u32; 24] = [
    0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5,
];
pub static SCALARS: [f32; 6] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
