//! Every normal handed to the renderer is the exact limit normal: within 0.05° of
//! the limit normal of the refined mesh's vertex at that point, computed in `f64` by
//! `Ring::limit_sided` (one-sided where the surface has a crease or a corner: the side whose
//! tangent plane is nearest the triangle's own plane), reversed where it points against the
//! triangle (`LimitMesh::normals_facing_faces`: OpenSubdiv's normal at a vertex of valence 2,
//! a coarse triangle folded against the surface).
//!
//! Uniform scenes: every fixture cage at depths 1 to 3. Adaptive frames: a few cages at mixed
//! per-face depths, checked against the limit points of the deepest level.

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use subdiv::LimitMesh;
use subdiv::depth::DepthParams;
use subdiv::mesh::{Camera, Mesh, VertexId, read_obj};
use subdiv::rules::{Ring, Scheme, refine_uniform_levels};
use subdiv::{DynamicSubdivision, Scene};

const MAX_DEGREES: f64 = 0.05;

/// Limit points of a refined mesh, with their normal and one-sided normals, found by position.
struct Truth {
    cell: f64,
    grid: HashMap<[i64; 3], Vec<usize>>,
    points: Vec<(DVec3, DVec3, Vec<DVec3>)>,
}

impl Truth {
    fn new(cage: &Mesh, scheme: Scheme, depth: u8) -> Truth {
        let refined = refine_uniform_levels(cage, scheme, depth).unwrap();
        let (lo, hi) = cage.bounds();
        let cell = f64::from((hi - lo).length().max(1e-6)) * 2e-5;
        let mut t = Truth {
            cell,
            grid: HashMap::new(),
            points: Vec::new(),
        };
        let mut ring = Ring::new();
        let mut faces = Vec::new();
        for v in refined.vertices() {
            if !ring.load(&refined, VertexId(v.0), scheme) {
                continue;
            }
            let (p, n) = ring.limit_sided(&mut faces);
            t.grid.entry(t.key(p)).or_default().push(t.points.len());
            t.points.push((p, n, faces.clone()));
        }
        t
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        (p / self.cell).floor().as_i64vec3().to_array()
    }

    /// The limit point at `p` (within a cell), if any.
    fn at(&self, p: Vec3) -> Option<&(DVec3, DVec3, Vec<DVec3>)> {
        let p = p.as_dvec3();
        let k = self.key(p);
        let mut best: Option<(f64, usize)> = None;
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let c = [k[0] + dx, k[1] + dy, k[2] + dz];
                    for &i in self.grid.get(&c).into_iter().flatten() {
                        let d = self.points[i].0.distance(p);
                        if d < self.cell && best.is_none_or(|(b, _)| d < b) {
                            best = Some((d, i));
                        }
                    }
                }
            }
        }
        best.map(|(_, i)| &self.points[i])
    }
}

/// What [`check`] found: corners checked, of those with one-sided normals, the worst angle in
/// degrees and where.
struct Checked {
    corners: usize,
    sided: usize,
    worst: f64,
    what: String,
}

/// Checks every triangle corner of `m` (a scene's split surface).
fn check(m: &LimitMesh, truth: &Truth) -> Checked {
    let (mut checked, mut sided, mut worst, mut what) = (0, 0, 0.0f64, String::new());
    for (t, tri) in m.face_indices().chunks(3).enumerate() {
        let p: Vec<Vec3> = tri
            .iter()
            .map(|&i| m.positions()[i as usize].into())
            .collect();
        let flat = (p[1] - p[0])
            .cross(p[2] - p[0])
            .as_dvec3()
            .normalize_or_zero();
        for (k, &i) in tri.iter().enumerate() {
            let Some((_, n, sides)) = truth.at(p[k]) else {
                panic!(
                    "triangle {t} corner {k} at {:?}: no limit point there",
                    p[k]
                );
            };
            let want = if sides.is_empty() {
                *n
            } else {
                *sides
                    .iter()
                    .max_by(|a, b| a.dot(flat).total_cmp(&b.dot(flat)))
                    .unwrap()
            };
            let got = Vec3::from(m.normals()[i as usize]).as_dvec3();
            let angle_to = |want: DVec3| {
                got.normalize()
                    .dot(want)
                    .clamp(-1.0, 1.0)
                    .acos()
                    .to_degrees()
            };
            // Drawn facing the triangle; a normal in the triangle's plane may go either way.
            let facing = want.dot(flat);
            let angle = if facing.abs() < 1e-6 {
                angle_to(want).min(angle_to(-want))
            } else {
                angle_to(want * facing.signum())
            };
            checked += 1;
            sided += usize::from(!sides.is_empty());
            if angle > worst || angle.is_nan() {
                worst = if angle.is_nan() { f64::INFINITY } else { angle };
                what = format!(
                    "triangle {t} corner {k} at {:?}: {got} vs {want} ({} sides)",
                    p[k],
                    sides.len()
                );
            }
        }
    }
    Checked {
        corners: checked,
        sided,
        worst,
        what,
    }
}

/// The fixture cages: the reference shapes and the scenes (the scenes hold the box with
/// infinitely sharp edges, the shapes few of those).
fn cages() -> Vec<(String, Mesh, Scheme)> {
    let root = subdiv_test_support::fixtures();
    let mut paths: Vec<_> = ["reference/shapes", "scenes"]
        .iter()
        .flat_map(|d| std::fs::read_dir(root.join(d)).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "obj"))
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            let scheme = if name.starts_with("loop") {
                Scheme::Loop
            } else {
                Scheme::CatmullClark
            };
            let mesh = read_obj(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
            (name, mesh, scheme)
        })
        .collect()
}

#[test]
fn uniform_scenes_hand_out_exact_limit_normals() {
    let cages = cages();
    assert!(cages.len() >= 30, "{} cages", cages.len());
    let mut failures = Vec::new();
    let (mut total, mut sided, mut worst_all) = (0, 0, 0.0f64);
    for (name, cage, scheme) in &cages {
        for depth in 1..=3 {
            let Ok(scene) = Scene::uniform(cage, *scheme, depth) else {
                continue;
            };
            let truth = Truth::new(cage, *scheme, depth);
            let Checked {
                corners,
                sided: s,
                worst,
                what,
            } = check(scene.surface(), &truth);
            (total, sided) = (total + corners, sided + s);
            worst_all = worst_all.max(worst);
            if worst > MAX_DEGREES {
                failures.push(format!("{name} depth {depth}: {worst:.4}° at {what}"));
            }
        }
    }
    println!("{total} corners ({sided} one-sided), worst {worst_all:.5}°");
    assert!(total > 100_000, "{total} corners");
    assert!(sided > 300, "{sided} one-sided corners");
    assert!(
        failures.is_empty(),
        "normals off the limit:\n{}",
        failures.join("\n")
    );
}

#[test]
fn adaptive_frames_hand_out_exact_limit_normals() {
    let cages = cages();
    let pick = [
        "catmark_cube_corner3",
        "catmark_tent_creases0",
        "catmark_pawn",
        "catmark_nonquads",
        "catmark_edgecorner",
        "catmark_single_crease",
        "box_8_sharp_edges",
    ];
    let (mut seen, mut sided) = (0, 0);
    let mut failures = Vec::new();
    for (name, cage, scheme) in &cages {
        if !pick.contains(&name.as_str()) || *scheme != Scheme::CatmullClark {
            continue;
        }
        seen += 1;
        let truth = Truth::new(cage, Scheme::CatmullClark, 3);
        let mut node = DynamicSubdivision::new(cage.clone(), DepthParams::default()).unwrap();
        let (lo, hi) = cage.bounds();
        let camera = Camera::eye_relative(lo, hi, Vec3::new(0.6, 0.5, 2.2), 45.0, 320, 240);
        let nf = cage.num_faces();
        for round in 0..3u32 {
            // Mixed depths 1..=3 (level-1 units need at least 1), different per round.
            let depths: Vec<u8> = (0..nf as u32)
                .map(|f| 1 + ((f * 7 + round * 5) % 3) as u8)
                .collect();
            node.set_face_depths(Some(depths)).unwrap();
            let g = node.update(&camera, None).unwrap();
            let scene = Scene::from_limit(&g.surface().referenced_only());
            let Checked {
                corners,
                sided: s,
                worst,
                what,
            } = check(scene.surface(), &truth);
            println!("{name} round {round}: {corners} corners ({s} one-sided), worst {worst:.5}°");
            sided += s;
            if worst > MAX_DEGREES {
                failures.push(format!("{name} round {round}: {worst:.4}° at {what}"));
            }
        }
    }
    assert_eq!(seen, pick.len(), "fixture cages missing");
    assert!(sided > 100, "{sided} one-sided corners");
    assert!(
        failures.is_empty(),
        "normals off the limit:\n{}",
        failures.join("\n")
    );
}
