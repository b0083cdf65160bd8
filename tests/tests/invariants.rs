//! Invariants of the rules over every fixture cage.

use subdiv_mesh::{ReadOptions, VertexId, read_obj_with};
use subdiv_rules::{Scheme, limit_point, refine_uniform_levels, tessellate_uniform};
use subdiv_tests::fixture_files;

fn scheme_of(path: &std::path::Path) -> Scheme {
    let name = path.file_name().unwrap().to_string_lossy();
    if name.starts_with("loop_") || name.starts_with("tri_") {
        Scheme::Loop
    } else {
        Scheme::CatmullClark
    }
}

fn cages() -> Vec<std::path::PathBuf> {
    let mut v = fixture_files("reference/shapes", "obj");
    v.extend(fixture_files("meshes", "obj"));
    v
}

/// An interior vertex of valence 2 with the smooth or dart rule and no semi-sharpness left.
fn valence2_smooth(mesh: &subdiv_mesh::Mesh, v: VertexId) -> bool {
    let s: Vec<f32> = mesh
        .outgoing(v)
        .map(|h| mesh.edge_sharpness(h.edge()))
        .collect();
    mesh.valence(v) == 2
        && !mesh.is_boundary_vertex(v)
        && mesh.vertex_sharpness(v) == 0.0
        && s.iter().all(|&x| x == 0.0 || x >= 10.0)
        && s.iter().filter(|&&x| x >= 10.0).count() < 2
}

/// The limit of a vertex is the limit of all its descendants: evaluating the cage vertices'
/// limits from the cage (refining their rings locally through every semi-sharp crease) must give
/// the same points as evaluating them two levels down.
#[test]
fn limit_points_are_level_invariant() {
    for path in cages() {
        let mesh = read_obj_with(
            &path,
            ReadOptions {
                split_nonmanifold_vertices: true,
            },
        )
        .unwrap();
        let scheme = scheme_of(&path);
        let (lo, hi) = mesh.bounds();
        let tol = 1e-5 * (hi - lo).length();
        let fine = refine_uniform_levels(&mesh, scheme, 2).unwrap();
        for v in mesh.vertices() {
            let (p0, n0) = limit_point(&mesh, v, scheme);
            let (p2, n2) = limit_point(&fine, v, scheme);
            if scheme == Scheme::CatmullClark && valence2_smooth(&mesh, v) {
                // OpenSubdiv gives these the corner masks: the "limit" is the vertex's position
                // at the level it is evaluated from, so it is not level invariant.
                assert_eq!(p0, mesh.position(v), "{}: vertex {v}", path.display());
                assert_eq!(p2, fine.position(v), "{}: vertex {v}", path.display());
                continue;
            }
            assert!(
                (p0 - p2).length() <= tol,
                "{}: vertex {v}: {p0} at level 0, {p2} at level 2",
                path.display()
            );
            // Normals agree wherever they are unique (smooth points).
            let smooth = mesh.vertex_sharpness(v) < 10.0
                && mesh
                    .outgoing(v)
                    .all(|h| mesh.edge_sharpness(h.edge()) < 10.0);
            if smooth {
                assert!(
                    n0.dot(n2) > 0.9999,
                    "{}: vertex {v}: normal {n0} at level 0, {n2} at level 2",
                    path.display()
                );
            }
        }
    }
}

/// Counts follow Euler's formula and every interior edge of the output has two faces.
#[test]
fn tessellation_counts_and_closure() {
    for path in cages() {
        let mesh = read_obj_with(
            &path,
            ReadOptions {
                split_nonmanifold_vertices: true,
            },
        )
        .unwrap();
        let scheme = scheme_of(&path);
        for depth in 0..=2 {
            let t = tessellate_uniform(&mesh, scheme, depth).unwrap();
            let refined = refine_uniform_levels(&mesh, scheme, depth).unwrap();
            assert_eq!(t.positions().len(), refined.num_vertices());
            assert_eq!(
                t.num_faces(),
                refined.faces().filter(|&f| !refined.is_hole(f)).count()
            );
            let chi = refined.num_vertices() as i64 - refined.num_edges() as i64
                + refined.num_faces() as i64;
            let chi0 =
                mesh.num_vertices() as i64 - mesh.num_edges() as i64 + mesh.num_faces() as i64;
            assert_eq!(
                chi,
                chi0,
                "{}: Euler characteristic changed at depth {depth}",
                path.display()
            );
            for p in t.positions() {
                assert!(p.iter().all(|c| c.is_finite()));
            }
            for n in t.normals() {
                let l = glam::Vec3::from(*n).length();
                assert!(
                    (l - 1.0).abs() < 1e-4,
                    "{}: normal of length {l}",
                    path.display()
                );
            }
            let _ = VertexId(0);
        }
    }
}
