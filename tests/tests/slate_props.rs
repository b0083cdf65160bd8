//! Property tests of the slate tessellator over every fixture cage: distinct points, closed
//! manifold output, thread-count independence, extreme valence, creases at every depth.

use std::collections::{HashMap, HashSet};

use glam::Vec3;
use subdiv_mesh::{Mesh, MeshStats, PolygonSoup};
use subdiv_rules::LimitMesh;

fn cages() -> Vec<(String, Mesh)> {
    subdiv_tests::catmull_clark_cages()
}

fn run(mesh: &Mesh, depth: subdiv_slate::Depth, threads: usize) -> LimitMesh {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| subdiv_slate::tessellate(mesh, depth).unwrap())
}

/// Edge -> number of faces using it (undirected), and directed-edge duplicates.
fn edge_use(t: &LimitMesh) -> (HashMap<(u32, u32), u32>, bool) {
    let mut und = HashMap::new();
    let mut dir = HashSet::new();
    let mut dup = false;
    for i in 0..t.num_faces() {
        let f = t.face(i);
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *und.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            dup |= !dir.insert((a, b));
        }
    }
    (und, dup)
}

#[test]
fn distinct_points_closed_output_and_thread_independence() {
    for (name, mesh) in cages() {
        let stats = MeshStats::of(&mesh);
        for depth in 0..=4 {
            let t1 = run(&mesh, depth, 1);
            let t2 = run(&mesh, depth, 2);
            // Bit-identical for 1 and 2 threads.
            assert_eq!(
                t1, t2,
                "{name} depth {depth}: output depends on the thread count"
            );
            // Every vertex is a distinct limit point (shared points stored once).
            let distinct: HashSet<[u32; 3]> =
                t1.positions().iter().map(|p| p.map(f32::to_bits)).collect();
            let referenced: HashSet<u32> = t1.face_indices().iter().copied().collect();
            assert_eq!(
                distinct.len(),
                t1.positions().len(),
                "{name} depth {depth}: repeated limit points"
            );
            assert_eq!(
                referenced.len() + stats.isolated_vertices,
                t1.positions().len(),
                "{name} depth {depth}: unreferenced vertices"
            );
            // Every edge has one or two faces, consistently oriented; only boundary edges have one,
            // and there are as many of them as the cage's boundary edges times 2^depth.
            let (und, dup) = edge_use(&t1);
            assert!(
                !dup,
                "{name} depth {depth}: a directed edge is used twice (orientation)"
            );
            assert!(
                und.values().all(|&c| c == 1 || c == 2),
                "{name} depth {depth}: non-manifold edge"
            );
            let open = und.values().filter(|&&c| c == 1).count();
            let holes = mesh.faces().filter(|&f| mesh.is_hole(f)).count();
            if holes == 0 {
                assert_eq!(
                    open,
                    stats.boundary_edges << depth,
                    "{name} depth {depth}: open edges"
                );
            }
            for n in t1.normals() {
                assert!(
                    (Vec3::from(*n).length() - 1.0).abs() < 1e-3,
                    "{name} depth {depth}: normal {n:?}"
                );
            }
        }
    }
}

/// Workers are kept by their threads between tessellations (inside `subdiv_slate`): a
/// worker that has served every other cage (its stencil cache full of their configurations)
/// gives the same bits as a fresh one.
#[test]
fn reused_workers_give_the_same_output() {
    let cages = cages();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let warm: Vec<LimitMesh> = pool.install(|| {
        for (_, mesh) in &cages {
            subdiv_slate::tessellate(mesh, 2).unwrap();
        }
        cages
            .iter()
            .rev()
            .map(|(_, m)| subdiv_slate::tessellate(m, 3).unwrap())
            .collect()
    });
    for ((name, mesh), w) in cages.iter().rev().zip(&warm) {
        assert_eq!(
            &run(mesh, 3, 1),
            w,
            "{name}: a reused worker changed the output"
        );
    }
}

/// A disk of `n` quads around a valence-`n` centre, lifted into a cone; boundary and interior.
fn pole(n: u32, closed: bool) -> Mesh {
    let mut p = vec![Vec3::new(0.0, 0.0, 1.0)];
    for i in 0..n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        p.push(Vec3::new(a.cos(), a.sin(), 0.0));
        let b = (i as f32 + 0.5) / n as f32 * std::f32::consts::TAU;
        p.push(Vec3::new(1.5 * b.cos(), 1.5 * b.sin(), -0.2));
    }
    let mut faces: Vec<Vec<u32>> = (0..n)
        .map(|i| {
            let a = 1 + 2 * i;
            let b = 1 + 2 * ((i + 1) % n);
            vec![0, a, a + 1, b]
        })
        .collect();
    if closed {
        // Close the underside with a second fan around a bottom pole.
        let bottom = p.len() as u32;
        p.push(Vec3::new(0.0, 0.0, -1.0));
        for i in 0..n {
            let a = 1 + 2 * i;
            let b = 1 + 2 * ((i + 1) % n);
            faces.push(vec![bottom, b, a + 1, a]);
        }
    }
    Mesh::from_soup(&PolygonSoup::from_faces(p, &faces)).unwrap()
}

#[test]
fn valence_360_pole() {
    for closed in [false, true] {
        let mesh = pole(360, closed);
        assert_eq!(mesh.max_valence(), 360);
        for depth in [1, 2] {
            let s = subdiv_slate::tessellate(&mesh, depth).unwrap();
            let r =
                subdiv_rules::tessellate_uniform(&mesh, subdiv_rules::Scheme::CatmullClark, depth)
                    .unwrap();
            assert_eq!(s.positions().len(), r.positions().len());
            // The pole's limit (vertex 0 in both) agrees.
            let (a, b) = (Vec3::from(s.positions()[0]), Vec3::from(r.positions()[0]));
            assert!((a - b).length() < 1e-5, "pole limit {a} vs {b}");
            assert!(Vec3::from(s.normals()[0]).dot(Vec3::Z) > 0.999);
            let (und, dup) = edge_use(&s);
            assert!(!dup && und.values().all(|&c| c <= 2));
        }
    }
}

#[test]
fn creases_at_every_depth() {
    // A cube with semi-sharp edges of sharpness 0.5 .. 6.5 on different edges: the slate output
    // equals the whole-mesh reference at every depth up to 5 (past every crease's end).
    let text = subdiv_test_support::cube().obj()
        + "t crease 2/1/0 0 1 0.5\nt crease 2/1/0 1 3 1.5\nt crease 2/1/0 3 2 2.5\nt crease 2/1/0 2 0 6.5\nt crease 2/1/0 4 5 10\nt corner 1/1/0 7 3.5\n";
    for chaikin in [false, true] {
        let text = if chaikin {
            format!("{text}t creasemethod 0/0/1 chaikin\n")
        } else {
            text.to_string()
        };
        let mesh = Mesh::from_soup(&subdiv_mesh::parse_obj(&text).unwrap()).unwrap();
        for depth in 0..=5 {
            let s = subdiv_slate::tessellate(&mesh, depth).unwrap();
            let r =
                subdiv_rules::tessellate_uniform(&mesh, subdiv_rules::Scheme::CatmullClark, depth)
                    .unwrap();
            let rp: HashSet<[i64; 3]> = r
                .positions()
                .iter()
                .map(|p| p.map(|c| (c * 1e5).round() as i64))
                .collect();
            let mut missing = 0;
            for p in s.positions() {
                let q = p.map(|c| (c * 1e5).round() as i64);
                // Allow rounding at the grid boundary: look at the neighbouring cells too.
                let found = (-1..=1).any(|dx| {
                    (-1..=1).any(|dy| {
                        (-1..=1).any(|dz| rp.contains(&[q[0] + dx, q[1] + dy, q[2] + dz]))
                    })
                });
                if !found {
                    missing += 1;
                }
            }
            assert_eq!(
                missing, 0,
                "chaikin={chaikin} depth {depth}: {missing} slate points not in the reference"
            );
            assert_eq!(s.positions().len(), r.positions().len());
        }
    }
}
