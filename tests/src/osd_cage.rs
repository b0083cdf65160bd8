//! Differential testing against OpenSubdiv, part 1: a random cage with OpenSubdiv's tags, written
//! as OBJ text that both `subdiv_mesh::parse_obj` and `xtask/osd/ref_osd.cpp` read, the
//! manifold check the generator ([`crate::osd_gen`]) keeps its cages valid with, and the
//! reductions the shrinker of `cargo xtask fuzz-osd` uses.
//!
//! Coordinates are multiples of 2^-10 and sharpness values multiples of 1/8, so the decimal text
//! means the same number to `f32` (subdiv) and `double`/`float` (OpenSubdiv).

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use subdiv_mesh::{Mesh, MeshError, parse_obj};

/// A random cage: positions, faces, tags and options. Always manifold and consistently oriented
/// (see [`is_manifold`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OsdCage {
    /// Vertex positions (multiples of 2^-10).
    pub positions: Vec<[f64; 3]>,
    /// Faces, 0-based, counter-clockwise.
    pub faces: Vec<Vec<u32>>,
    /// Sharp edges: two vertex indices and a sharpness.
    pub creases: Vec<(u32, u32, f32)>,
    /// Sharp vertices and their sharpness.
    pub corners: Vec<(u32, f32)>,
    /// Hole faces.
    pub holes: Vec<u32>,
    /// `t interpolateboundary` value (0 none, 1 edge-and-corner, 2 edge-only); `None`: no tag.
    pub boundary: Option<u8>,
    /// `t creasemethod`: `Some(true)` chaikin, `Some(false)` uniform, `None` no tag.
    pub chaikin: Option<bool>,
    /// `t smoothtriangles`: `Some(true)` smooth, `Some(false)` catmark, `None` no tag.
    pub smooth_triangles: Option<bool>,
    /// Loop (every face a triangle) instead of Catmull-Clark.
    pub loop_scheme: bool,
}

impl OsdCage {
    /// The OBJ text (`v`, `f` and `t` lines) of the cage.
    pub fn to_obj(&self) -> String {
        let mut s = String::new();
        let scheme = if self.loop_scheme { "loop" } else { "catmark" };
        let _ = writeln!(s, "# osd-fuzz cage, scheme {scheme}");
        for p in &self.positions {
            let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
        }
        for f in &self.faces {
            s.push('f');
            for &v in f {
                let _ = write!(s, " {}", v + 1);
            }
            s.push('\n');
        }
        for &(a, b, w) in &self.creases {
            let _ = writeln!(s, "t crease 2/1/0 {a} {b} {w}");
        }
        for &(v, w) in &self.corners {
            let _ = writeln!(s, "t corner 1/1/0 {v} {w}");
        }
        if !self.holes.is_empty() {
            let _ = write!(s, "t hole {}/0/0", self.holes.len());
            for h in &self.holes {
                let _ = write!(s, " {h}");
            }
            s.push('\n');
        }
        if let Some(b) = self.boundary {
            let _ = writeln!(s, "t interpolateboundary 1/0/0 {b}");
        }
        if let Some(c) = self.chaikin {
            let m = if c { "chaikin" } else { "uniform" };
            let _ = writeln!(s, "t creasemethod 0/0/1 {m}");
        }
        if let Some(t) = self.smooth_triangles {
            let m = if t { "smooth" } else { "catmark" };
            let _ = writeln!(s, "t smoothtriangles 0/0/1 {m}");
        }
        s
    }

    /// The cage as subdiv reads it (through its OBJ text, as `ref_osd` does).
    pub fn mesh(&self) -> Result<Mesh, MeshError> {
        let mut soup = parse_obj(&self.to_obj())?;
        soup.split_nonmanifold()?;
        Mesh::from_soup(&soup)
    }

    /// `ref_osd`'s scheme argument.
    pub fn scheme_name(&self) -> &'static str {
        if self.loop_scheme { "loop" } else { "catmark" }
    }

    /// A one-line summary of the cage's features (for classifying disagreements).
    pub fn features(&self) -> String {
        let sizes = |lo: usize, hi: usize| {
            self.faces
                .iter()
                .filter(|f| (lo..=hi).contains(&f.len()))
                .count()
        };
        let kind = |s: f32| {
            if s >= subdiv_mesh::SHARPNESS_INFINITE {
                "inf"
            } else if s.fract() == 0.0 {
                "int"
            } else {
                "frac"
            }
        };
        let kinds = |v: &mut dyn Iterator<Item = f32>| {
            let mut k: Vec<&str> = v.map(kind).collect();
            k.sort_unstable();
            k.dedup();
            k.join("+")
        };
        format!(
            "{} F={} (tri {} quad {} ngon {}) V={} valence2={} holes={} creases={}[{}] \
             corners={}[{}] boundary={:?} chaikin={:?} smoothtri={:?} nonmanifold={}",
            self.scheme_name(),
            self.faces.len(),
            sizes(3, 3),
            sizes(4, 4),
            sizes(5, usize::MAX),
            self.positions.len(),
            self.interior_valence2(),
            self.holes.len(),
            self.creases.len(),
            kinds(&mut self.creases.iter().map(|c| c.2)),
            self.corners.len(),
            kinds(&mut self.corners.iter().map(|c| c.1)),
            self.boundary,
            self.chaikin,
            self.smooth_triangles,
            self.nonmanifold_summary()
        )
    }

    /// `none`, or the non-manifold edges and vertices and the bare vertices
    /// (`PolygonSoup::split_nonmanifold`), e.g. `e2v3b1`.
    pub fn nonmanifold_summary(&self) -> String {
        let found = parse_obj(&self.to_obj()).map(|mut s| s.split_nonmanifold());
        match found {
            Ok(Ok(n)) if !n.is_empty() || !n.bare.is_empty() => {
                format!("e{}v{}b{}", n.edges.len(), n.vertices.len(), n.bare.len())
            }
            Ok(Ok(_)) => "none".into(),
            _ => "refused".into(),
        }
    }

    /// Number of interior vertices with two faces (the faces share two consecutive edges).
    pub fn interior_valence2(&self) -> usize {
        let mut directed = HashSet::new();
        let mut count = vec![0usize; self.positions.len()];
        for f in &self.faces {
            for k in 0..f.len() {
                directed.insert((f[k], f[(k + 1) % f.len()]));
                count[f[k] as usize] += 1;
            }
        }
        let mut boundary = vec![false; self.positions.len()];
        for &(a, b) in &directed {
            if !directed.contains(&(b, a)) {
                boundary[a as usize] = true;
                boundary[b as usize] = true;
            }
        }
        (0..count.len())
            .filter(|&v| count[v] == 2 && !boundary[v])
            .count()
    }

    /// The largest finite (semi-sharp) sharpness of any tag, 0 without one.
    pub fn max_semi_sharpness(&self) -> f32 {
        let c = self.creases.iter().map(|c| c.2);
        let v = self.corners.iter().map(|c| c.1);
        c.chain(v)
            .filter(|&s| s < subdiv_mesh::SHARPNESS_INFINITE)
            .fold(0.0, f32::max)
    }

    /// The cage's undirected edges, each once as `(min, max)`, in face order.
    pub fn edges(&self) -> Vec<(u32, u32)> {
        let mut seen = HashSet::new();
        let mut out = Vec::new();
        for f in &self.faces {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                let e = (a.min(b), a.max(b));
                if seen.insert(e) {
                    out.push(e);
                }
            }
        }
        out
    }

    /// Removes face `f` (and its hole tag), drops vertices no face uses any more and the tags
    /// on them or on edges that no longer exist. `None` when what is left is empty or not
    /// manifold.
    pub fn without_face(&self, f: usize) -> Option<OsdCage> {
        let mut c = self.clone();
        c.faces.remove(f);
        c.holes = c
            .holes
            .iter()
            .filter(|&&h| h as usize != f)
            .map(|&h| if h as usize > f { h - 1 } else { h })
            .collect();
        c.compact();
        let ok = !c.faces.is_empty()
            && c.holes.len() < c.faces.len()
            && (is_manifold(&c.faces, c.positions.len()) || c.mesh().is_ok());
        ok.then_some(c)
    }

    /// Renumbers the vertices in use (in their order) and drops the tags that no longer apply.
    pub fn compact(&mut self) {
        let mut map = vec![u32::MAX; self.positions.len()];
        let mut pos = Vec::new();
        for f in &mut self.faces {
            for v in f.iter_mut() {
                if map[*v as usize] == u32::MAX {
                    map[*v as usize] = pos.len() as u32;
                    pos.push(self.positions[*v as usize]);
                }
                *v = map[*v as usize];
            }
        }
        self.positions = pos;
        let edges: HashSet<(u32, u32)> = self.edges().into_iter().collect();
        self.creases = self
            .creases
            .iter()
            .map(|&(a, b, s)| (map[a as usize], map[b as usize], s))
            .filter(|&(a, b, _)| edges.contains(&(a.min(b), a.max(b))))
            .collect();
        self.corners = self
            .corners
            .iter()
            .map(|&(v, s)| (map[v as usize], s))
            .filter(|&(v, _)| v != u32::MAX)
            .collect();
    }

    /// Every cage one step simpler: one tag or option dropped, or one face removed (largest
    /// reductions first). The shrinker keeps the first that still fails.
    pub fn reductions(&self) -> Vec<OsdCage> {
        let mut out = Vec::new();
        for f in (0..self.faces.len()).rev() {
            out.extend(self.without_face(f));
        }
        for i in 0..self.creases.len() {
            let mut c = self.clone();
            c.creases.remove(i);
            out.push(c);
        }
        for i in 0..self.corners.len() {
            let mut c = self.clone();
            c.corners.remove(i);
            out.push(c);
        }
        for i in 0..self.holes.len() {
            let mut c = self.clone();
            c.holes.remove(i);
            out.push(c);
        }
        let mut c = self.clone();
        c.boundary = None;
        c.chaikin = None;
        c.smooth_triangles = None;
        if c != *self {
            out.push(c);
        }
        out
    }
}

/// `true` when `faces` is a manifold, consistently oriented polygon mesh on vertices `0..nv`:
/// every face has at least 3 distinct vertices, no directed edge is used twice, no two faces
/// have the same vertex set, no vertex has more than 20 faces, and the faces around every used
/// vertex form a single fan.
pub fn is_manifold(faces: &[Vec<u32>], nv: usize) -> bool {
    let mut directed = HashSet::new();
    let mut sets = HashSet::new();
    // Per vertex: (face, previous vertex, next vertex) of each corner.
    let mut corners: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    for f in faces {
        let n = f.len();
        let distinct: HashSet<u32> = f.iter().copied().collect();
        if n < 3 || distinct.len() != n || f.iter().any(|&v| v as usize >= nv) {
            return false;
        }
        let mut key: Vec<u32> = f.clone();
        key.sort_unstable();
        if !sets.insert(key) {
            return false;
        }
        for k in 0..n {
            if !directed.insert((f[k], f[(k + 1) % n])) {
                return false;
            }
            corners
                .entry(f[k])
                .or_default()
                .push((f[(k + n - 1) % n], f[(k + 1) % n]));
        }
    }
    corners.values().all(|c| c.len() <= 20 && single_fan(c))
}

/// The corners `(prev, next)` around one vertex form one fan: walking from a start corner to
/// the corner whose `prev` is this one's `next` reaches every corner.
fn single_fan(corners: &[(u32, u32)]) -> bool {
    let by_prev: HashMap<u32, usize> = corners.iter().enumerate().map(|(i, c)| (c.0, i)).collect();
    // Start at a corner nobody continues into (a boundary fan's first face), if any.
    let nexts: HashSet<u32> = corners.iter().map(|c| c.1).collect();
    let start = corners
        .iter()
        .position(|c| !nexts.contains(&c.0))
        .unwrap_or(0);
    let mut seen = vec![false; corners.len()];
    let mut i = start;
    let mut count = 0;
    while !seen[i] {
        seen[i] = true;
        count += 1;
        match by_prev.get(&corners[i].1) {
            Some(&j) => i = j,
            None => break,
        }
    }
    count == corners.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifold_check_rejects_bowties_and_flips() {
        let quad = vec![vec![0, 1, 2, 3]];
        assert!(is_manifold(&quad, 4));
        // Two triangles touching at vertex 0 only: a bow-tie.
        assert!(!is_manifold(&[vec![0, 1, 2], vec![0, 3, 4]], 5));
        // A flipped neighbour repeats the directed edge 0->1.
        assert!(!is_manifold(&[vec![0, 1, 2], vec![0, 1, 3]], 4));
        // A doubled triangle.
        assert!(!is_manifold(&[vec![0, 1, 2], vec![0, 2, 1]], 3));
        // Two quads back to back around the valence-2 vertex 0.
        assert!(is_manifold(&[vec![0, 1, 2, 3], vec![0, 3, 4, 1]], 5));
    }

    #[test]
    fn removing_a_face_keeps_the_tags_that_apply() {
        let c = OsdCage {
            positions: vec![[0.0; 3]; 6],
            faces: vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]],
            creases: vec![(1, 4, 2.0), (2, 5, 1.0)],
            corners: vec![(5, 3.0), (0, 1.0)],
            ..OsdCage::default()
        };
        let d = c.without_face(1).expect("one quad is left");
        assert_eq!(d.faces, vec![vec![0, 1, 2, 3]]);
        assert_eq!(d.creases, vec![(1, 2, 2.0)]);
        assert_eq!(d.corners, vec![(0, 1.0)]);
        assert!(d.mesh().is_ok());
    }
}
