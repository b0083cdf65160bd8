//! Helpers for subdiv's end-to-end tests: fixture paths, OpenSubdiv reference files and point
//! matching.

use std::collections::HashMap;
use std::path::PathBuf;

use glam::DVec3;

pub use subdiv_test_support::{fixture_files, fixtures};

/// An OpenSubdiv reference limit file (`fixtures/reference/limit/<shape>.L<n>.txt`).
#[derive(Debug, Clone)]
pub struct Reference {
    /// Header key=value pairs.
    pub header: HashMap<String, String>,
    /// Limit positions.
    pub positions: Vec<DVec3>,
    /// Limit normals.
    pub normals: Vec<DVec3>,
    /// Faces (0-based indices into positions).
    pub faces: Vec<Vec<usize>>,
}

impl Reference {
    /// Parses a reference file.
    pub fn read(path: &std::path::Path) -> Reference {
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        Self::parse(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    /// Parses the text of a reference file (as `xtask/osd/ref_osd.cpp` prints it).
    pub fn parse(text: &str) -> Result<Reference, String> {
        let mut lines = text.lines();
        let head = lines.next().ok_or("empty reference file")?;
        let mut header = HashMap::new();
        let toks: Vec<&str> = head.split_whitespace().collect();
        if toks.len() < 3 || toks[0] != "osdref" {
            return Err(format!("not a reference file: {head:?}"));
        }
        header.insert("V".into(), toks[1].into());
        header.insert("F".into(), toks[2].into());
        for t in &toks[3..] {
            if let Some((k, v)) = t.split_once('=') {
                header.insert(k.into(), v.into());
            }
        }
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let mut faces = Vec::new();
        for l in lines {
            let mut it = l.split_whitespace();
            match it.next() {
                Some("p") => {
                    let x: Vec<f64> = it.map(|t| t.parse().unwrap_or(f64::NAN)).collect();
                    if x.len() != 6 {
                        return Err(format!("bad point line {l:?}"));
                    }
                    positions.push(DVec3::new(x[0], x[1], x[2]));
                    normals.push(DVec3::new(x[3], x[4], x[5]));
                }
                Some("f") => faces.push(
                    it.map(|t| t.parse().map_err(|_| format!("bad face line {l:?}")))
                        .collect::<Result<_, _>>()?,
                ),
                _ => {}
            }
        }
        let r = Reference {
            header,
            positions,
            normals,
            faces,
        };
        for key in ["V", "F", "base_verts"] {
            if r.header
                .get(key)
                .and_then(|v| v.parse::<usize>().ok())
                .is_none()
            {
                return Err(format!("header has no number {key}"));
            }
        }
        if r.positions.len() != r.num("V") || r.faces.len() != r.num("F") {
            return Err("point or face count differs from the header".into());
        }
        if r.faces.iter().flatten().any(|&i| i >= r.positions.len()) {
            return Err("face index out of range".into());
        }
        Ok(r)
    }

    /// A header value parsed as a number.
    pub fn num(&self, key: &str) -> usize {
        self.header[key]
            .parse()
            .unwrap_or_else(|_| panic!("header {key}"))
    }
}

/// A uniform-grid spatial hash for nearest-point queries within a small radius.
pub struct PointGrid {
    cell: f64,
    map: HashMap<(i64, i64, i64), Vec<usize>>,
    points: Vec<DVec3>,
}

impl PointGrid {
    /// Indexes `points` with cells of size `cell`.
    pub fn new(points: &[DVec3], cell: f64) -> PointGrid {
        let mut map: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
        for (i, p) in points.iter().enumerate() {
            map.entry(Self::key(*p, cell)).or_default().push(i);
        }
        PointGrid {
            cell,
            map,
            points: points.to_vec(),
        }
    }
    fn key(p: DVec3, cell: f64) -> (i64, i64, i64) {
        (
            (p.x / cell).floor() as i64,
            (p.y / cell).floor() as i64,
            (p.z / cell).floor() as i64,
        )
    }
    /// The nearest indexed point within one cell of `p` (index and distance), else the global
    /// nearest by brute force.
    pub fn nearest(&self, p: DVec3) -> (usize, f64) {
        let (kx, ky, kz) = Self::key(p, self.cell);
        let mut best = (usize::MAX, f64::INFINITY);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(ids) = self.map.get(&(kx + dx, ky + dy, kz + dz)) {
                        for &i in ids {
                            let d = (self.points[i] - p).length();
                            if d < best.1 {
                                best = (i, d);
                            }
                        }
                    }
                }
            }
        }
        if best.0 == usize::MAX || best.1 > self.cell {
            for (i, q) in self.points.iter().enumerate() {
                let d = (*q - p).length();
                if d < best.1 {
                    best = (i, d);
                }
            }
        }
        best
    }
}

/// A polygon as a canonical key: rotated so the smallest index comes first.
pub fn canonical_face(f: &[usize]) -> Vec<usize> {
    let k = (0..f.len()).min_by_key(|&i| f[i]).unwrap_or(0);
    (0..f.len()).map(|i| f[(k + i) % f.len()]).collect()
}

/// Every Catmull-Clark fixture cage (OpenSubdiv's `catmark_*` shapes and the real meshes), read
/// with non-manifold vertices split, with its file stem.
pub fn catmull_clark_cages() -> Vec<(String, subdiv_mesh::Mesh)> {
    let mut v: Vec<PathBuf> = fixture_files("reference/shapes", "obj")
        .into_iter()
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("catmark_"))
        })
        .collect();
    v.extend(fixture_files("meshes", "obj"));
    v.into_iter()
        .map(|p| {
            let opts = subdiv_mesh::ReadOptions {
                split_nonmanifold_vertices: true,
            };
            let m = subdiv_mesh::read_obj_with(&p, opts).unwrap_or_else(|e| panic!("{e}"));
            (
                p.file_stem()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .to_string(),
                m,
            )
        })
        .collect()
}

/// Every Loop fixture cage (OpenSubdiv's `loop_*` shapes and the triangle meshes), read with
/// non-manifold vertices split, with its file stem.
pub fn loop_cages() -> Vec<(String, subdiv_mesh::Mesh)> {
    let mut v: Vec<PathBuf> = fixture_files("reference/shapes", "obj")
        .into_iter()
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("loop_"))
        })
        .collect();
    v.extend(fixture_files("meshes", "obj").into_iter().filter(|p| {
        p.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("tri_"))
    }));
    v.into_iter()
        .map(|p| {
            let opts = subdiv_mesh::ReadOptions {
                split_nonmanifold_vertices: true,
            };
            let m = subdiv_mesh::read_obj_with(&p, opts).unwrap_or_else(|e| panic!("{e}"));
            let name = p
                .file_stem()
                .unwrap_or_default()
                .to_string_lossy()
                .to_string();
            (name, m)
        })
        .collect()
}

pub mod eval_compare;
pub mod fuzz;
pub mod fuzz_check;
pub mod fuzz_lines;
pub mod fuzz_topo;
pub mod fuzz_usd;
pub mod osd_cage;
pub mod osd_compare;
pub mod osd_fvar;
pub mod osd_gen;
