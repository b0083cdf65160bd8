//! Summaries of adaptive frames ([`AdaptiveFrame`]).

use subdiv_stitch::AdaptiveFrame;

/// `0:a 1:b ...` patches (cage faces) per depth, with the culled count.
pub fn depth_histogram(g: &AdaptiveFrame) -> String {
    let per: Vec<String> = g
        .units_per_depth()
        .iter()
        .enumerate()
        .map(|(d, n)| format!("{d}:{n}"))
        .collect();
    let culled = g.unit_depth().iter().filter(|&&d| d == u8::MAX).count();
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
    fn referenced_frames_keep_their_vertices_and_depths() {
        let cube = &subdiv_test_support::cube().obj();
        let mesh = Mesh::from_soup(&parse_obj(cube).unwrap()).unwrap();
        let (lo, hi) = mesh.bounds();
        let mut node = DynamicSubdivision::new(mesh, DepthParams::default()).unwrap();
        let camera = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 320, 240);
        let g = node.update(&camera, None).unwrap();
        let limit = g.surface().referenced_only();
        assert_eq!(limit.num_faces(), g.num_triangles());
        let (_, depths) = limit.scalar().unwrap();
        assert_eq!(depths.len(), limit.num_vertices());
        assert!(limit.num_vertices() <= g.surface().num_vertices());
        limit.check().unwrap();
        let histogram = depth_histogram(g);
        assert!(histogram.starts_with("0:"), "{histogram}");
        let patches: usize = histogram
            .split(' ')
            .filter_map(|t| t.split_once(':').and_then(|(_, n)| n.parse::<usize>().ok()))
            .sum();
        assert_eq!(patches, 6, "{histogram}");
    }

    /// Angle in degrees between two unit vectors.
    fn angle(a: [f32; 3], b: [f32; 3]) -> f32 {
        let (a, b) = (Vec3::from(a), Vec3::from(b));
        a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
    }

    #[test]
    fn adaptive_frames_carry_the_one_sided_normals_of_the_uniform_path() {
        let path = subdiv_test_support::fixture("scenes/box_8_sharp_edges.obj");
        let mesh = subdiv_mesh::read_obj(path).unwrap();
        let truth = crate::uniform_limit(&mesh, subdiv_rules::Scheme::CatmullClark, 4).unwrap();
        // The uniform path's one-sided normals per point (by position).
        let mut sides: Vec<([f32; 3], Vec<[f32; 3]>)> = Vec::new();
        for &(c, n) in truth.corner_normals() {
            let p = truth.positions()[truth.face_indices()[c as usize] as usize];
            match sides
                .iter_mut()
                .find(|(q, _)| Vec3::from(*q).distance(p.into()) < 1e-5)
            {
                Some((_, ns)) => ns.push(n),
                None => sides.push((p, vec![n])),
            }
        }
        assert!(!sides.is_empty());
        let mut node = DynamicSubdivision::new(mesh.clone(), DepthParams::default()).unwrap();
        let (lo, hi) = mesh.bounds();
        let camera = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 320, 240);
        // Mixed depths: every sharp edge between two depths, so that fans run along creases.
        for depths in [
            [4u8, 1, 2, 3, 1, 4],
            [1, 4, 3, 2, 4, 2],
            [2, 2, 4, 1, 3, 3],
            [4; 6],
        ] {
            node.set_face_depths(Some(depths.to_vec())).unwrap();
            let g = node.update(&camera, None).unwrap();
            let limit = g.surface().referenced_only();
            let mut checked = 0;
            for (t, tri) in limit.face_indices().chunks(3).enumerate() {
                let p: Vec<Vec3> = tri
                    .iter()
                    .map(|&i| limit.positions()[i as usize].into())
                    .collect();
                let flat = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                for (k, &pk) in p.iter().enumerate() {
                    let Some((_, ns)) = sides
                        .iter()
                        .find(|(q, _)| Vec3::from(*q).distance(pk) < 1e-5)
                    else {
                        continue;
                    };
                    let c = (3 * t + k) as u32;
                    let got = limit
                        .corner_normals()
                        .binary_search_by_key(&c, |&(i, _)| i)
                        .map(|x| limit.corner_normals()[x].1)
                        .unwrap_or_else(|_| {
                            panic!("{depths:?}: corner {c} at {:?} has no one-sided normal", pk)
                        });
                    // The uniform side of this triangle: the one nearest its plane.
                    let want = ns
                        .iter()
                        .copied()
                        .min_by(|a, b| angle(*a, flat.into()).total_cmp(&angle(*b, flat.into())))
                        .unwrap();
                    let err = Vec3::from(got).distance(want.into());
                    assert!(
                        err < 1e-4,
                        "{depths:?}: corner {c} at {:?}: {got:?} vs {want:?}",
                        pk
                    );
                    checked += 1;
                }
            }
            assert!(checked > 100, "{depths:?}: only {checked} crease corners");
        }
    }
}
