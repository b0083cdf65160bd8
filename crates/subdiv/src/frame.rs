//! Frames of the adaptive tessellation ([`FrameGeometry`]) in the terms of a uniform one.

use subdiv_rules::LimitMesh;
use subdiv_stitch::FrameGeometry;

/// The triangles of an adaptive frame as a [`LimitMesh`] (referenced vertices only) and the
/// per-vertex depths of their patches.
pub fn frame_limit(g: &FrameGeometry) -> (LimitMesh, Vec<f32>) {
    let mut map = vec![u32::MAX; g.positions.len()];
    let mut limit = LimitMesh {
        positions: Vec::new(),
        normals: Vec::new(),
        face_offsets: (0..=g.indices.len() as u32 / 3).map(|i| i * 3).collect(),
        face_indices: Vec::with_capacity(g.indices.len()),
        corner_normals: Vec::new(),
    };
    let mut depths = Vec::new();
    for &i in &g.indices {
        let m = &mut map[i as usize];
        if *m == u32::MAX {
            *m = limit.positions.len() as u32;
            limit.positions.push(g.positions[i as usize]);
            limit.normals.push(g.normals[i as usize]);
            depths.push(g.vertex_depth[i as usize]);
        }
        limit.face_indices.push(*m);
    }
    (limit, depths)
}

/// `0:a 1:b ...` patches (cage faces) per depth, with the culled count.
pub fn depth_histogram(g: &FrameGeometry) -> String {
    let per: Vec<String> = g
        .units_per_depth()
        .iter()
        .enumerate()
        .map(|(d, n)| format!("{d}:{n}"))
        .collect();
    let culled = g.unit_depth.iter().filter(|&&d| d == u8::MAX).count();
    let mut s = per.join(" ");
    if culled > 0 {
        s.push_str(&format!(" culled:{culled}"));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DynamicSubdivision;
    use subdiv_depth::DepthParams;
    use subdiv_mesh::{Camera, Mesh, glam::Vec3, parse_obj};

    #[test]
    fn frame_limit_keeps_referenced_vertices_and_their_depths() {
        let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
                    f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
        let mesh = Mesh::from_soup(&parse_obj(cube).unwrap()).unwrap();
        let (lo, hi) = mesh.bounds();
        let mut node = DynamicSubdivision::new(mesh, DepthParams::default()).unwrap();
        let camera = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 320, 240);
        let g = node.update(&camera, None).unwrap();
        let (limit, depths) = frame_limit(g);
        assert_eq!(limit.num_faces(), g.num_triangles());
        assert_eq!(depths.len(), limit.positions.len());
        assert!(limit.positions.len() <= g.positions.len());
        assert!(
            limit
                .face_indices
                .iter()
                .all(|&i| (i as usize) < limit.positions.len())
        );
        let histogram = depth_histogram(g);
        assert!(histogram.starts_with("0:"), "{histogram}");
        let patches: usize = histogram
            .split(' ')
            .filter_map(|t| t.split_once(':').and_then(|(_, n)| n.parse::<usize>().ok()))
            .sum();
        assert_eq!(patches, 6, "{histogram}");
    }
}
