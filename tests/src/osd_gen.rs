//! Differential testing against OpenSubdiv, part 2: a seeded generator of random valid cages
//! ([`OsdCage`]) for `cargo xtask fuzz-osd` and the adaptive watertightness test.
//!
//! A cage starts as one of: an open quad or triangle grid; a tube (open, or closed with n-gon
//! caps or triangle-fan poles of valence up to 20); a torus; a pole of valence 2 to 20 (a fan of
//! triangles or quads, open or wrapped, or a closed bipyramid). Then random steps change its
//! topology, each kept only while the cage stays manifold ([`crate::osd_cage::is_manifold`]):
//! quads split into triangles, n-gons split along a diagonal, neighbours merged into n-gons of
//! up to 8 sides, edges split in two (the new vertex has valence 2: its two faces share two
//! consecutive edges), faces removed (boundaries). Loop cages are triangulated at the end. Then
//! tags: holes, creases and corners (infinite, integer and fractional sharpness), the boundary
//! interpolation, crease method and triangle rule. Positions are jittered and rounded to
//! multiples of 2^-10.
//!
//! A share of the cages ([`NONMANIFOLD_PERCENT`]) is then made non-manifold: fins (an edge with
//! three faces, or two the same way round), closed tetrahedra sharing an edge (four faces),
//! pyramids touching the cage at one vertex (bow-ties), fin strips (two fins on consecutive
//! edges: a vertex with exactly two non-manifold edges, half of them with a semi-sharp vertex
//! sharpness), and now and then a bare vertex; subdiv
//! refines them as OpenSubdiv does (`PolygonSoup::split_nonmanifold`).
//!
//! Every cage the generator finishes is meant to be valid, so it never hides a refusal:
//! [`draw_cage`] reports each finished cage that subdiv refused before the one it returns
//! ([`Draw::refused`]) and a sharpened form that subdiv refused, where the unsharpened cage is
//! returned in its place ([`Draw::fell_back`]). `cargo xtask fuzz-osd` counts both as
//! disagreements. (Redraws before a cage is finished, for a triangulation or a topology step
//! that is not manifold, are the generator's own and involve no subdiv code.)
//!
//! Of the cages with `interpolateboundary none`, a share
//! ([`boundary_none::SHARP_NONE_PERCENT`], from a stream of their own) get infinite crease
//! tags on every boundary edge, or on every boundary edge at a few boundary vertices: vertices
//! whose faces OpenSubdiv draws under `none`.

use std::f64::consts::TAU;

use crate::fuzz::Rng;
use crate::osd_cage::{OsdCage, is_manifold};

/// Cage `index` of the run with `seed` (independent of the other indices): the cage of
/// [`draw_cage`], whatever subdiv refused on the way.
pub fn random_cage(seed: u64, index: u64) -> OsdCage {
    draw_cage(seed, index).cage
}

/// A finished cage that subdiv refused, with its error.
#[derive(Clone, Debug)]
pub struct Refusal {
    /// The cage as drawn.
    pub cage: OsdCage,
    /// subdiv's error.
    pub error: String,
}

/// One draw of the generator: the cage, and every finished cage subdiv refused on the way.
#[derive(Clone, Debug)]
pub struct Draw {
    /// The cage drawn.
    pub cage: OsdCage,
    /// Finished cages refused before `cage`, each redrawn (in order).
    pub refused: Vec<Refusal>,
    /// The sharpened-boundary form of `cage` (see [`boundary_none`]), refused, in whose place
    /// `cage` (its simpler, unsharpened form) is returned.
    pub fell_back: Option<Refusal>,
}

impl Draw {
    /// The first refusal of a cage the generator meant to be valid, if any.
    pub fn first_refusal(&self) -> Option<&Refusal> {
        self.refused.first().or(self.fell_back.as_ref())
    }
}

/// Cage `index` of the run with `seed`, with what subdiv refused while drawing it.
pub fn draw_cage(seed: u64, index: u64) -> Draw {
    draw_cage_with(seed, index, &|c| {
        c.mesh().map(drop).map_err(|e| e.to_string())
    })
}

/// [`draw_cage`] with `accept` in place of subdiv's own validation (for tests of the
/// accounting): a cage `accept` refuses is recorded and redrawn as subdiv's refusals are.
pub fn draw_cage_with(
    seed: u64,
    index: u64,
    accept: &dyn Fn(&OsdCage) -> Result<(), String>,
) -> Draw {
    let mut refused = Vec::new();
    let mut rng = Rng::for_case(seed ^ 0x05D0_05D0, index);
    // Its own stream, so that the manifold cages are the ones earlier runs drew at each index.
    let mut nm_rng = Rng::for_case(seed ^ 0x0A0B_0C0D, index);
    let loop_scheme = rng.chance(30);
    loop {
        let mut b = base_shape(&mut rng, loop_scheme);
        mutate(&mut rng, &mut b, loop_scheme);
        if loop_scheme && !b.triangulate(&mut rng) {
            continue;
        }
        if b.faces.is_empty() || !is_manifold(&b.faces, b.pos.len()) {
            continue;
        }
        let nonmanifold = nm_rng.chance(NONMANIFOLD_PERCENT);
        let (mut corners, mut creases) = (Vec::new(), Vec::new());
        if nonmanifold {
            // Its own stream for the creases at fin strips, so the non-manifold shapes stay
            // the ones earlier runs drew.
            let mut crease_rng = Rng::for_case(seed ^ 0x0C4E_A5E0, index);
            // And for the closed fans at fin strips (crease copies).
            let mut copy_rng = Rng::for_case(seed ^ 0x0C0F_1E5D, index);
            (corners, creases) = add_nonmanifold(
                &mut nm_rng,
                &mut crease_rng,
                &mut copy_rng,
                &mut b,
                loop_scheme,
            );
        }
        let mut cage = OsdCage {
            positions: b.pos,
            faces: b.faces,
            corners,
            creases,
            loop_scheme,
            ..OsdCage::default()
        };
        cage.compact();
        if nonmanifold && nm_rng.chance(25) {
            // A bare vertex (no face uses it) near the first.
            let p = cage.positions[0];
            cage.positions.push([p[0] + 0.5, p[1] - 0.25, p[2] + 0.75]);
        }
        jitter(&mut rng, &mut cage);
        add_tags(&mut rng, &mut cage);
        if let Err(error) = accept(&cage) {
            refused.push(Refusal { cage, error });
            continue;
        }
        // Its own stream too: the other cages stay the ones earlier runs drew.
        let mut none_rng = Rng::for_case(seed ^ 0x0B0D_0000, index);
        let mut fell_back = None;
        if cage.boundary == Some(0) && none_rng.chance(boundary_none::SHARP_NONE_PERCENT) {
            let mut sharp = cage.clone();
            boundary_none::sharpen_boundary(&mut none_rng, &mut sharp);
            match accept(&sharp) {
                Ok(()) => {
                    return Draw {
                        cage: sharp,
                        refused,
                        fell_back,
                    };
                }
                Err(error) => fell_back = Some(Refusal { cage: sharp, error }),
            }
        }
        return Draw {
            cage,
            refused,
            fell_back,
        };
    }
}

/// A cage under construction.
#[derive(Clone, Debug, Default)]
struct Builder {
    pos: Vec<[f64; 3]>,
    faces: Vec<Vec<u32>>,
}

impl Builder {
    fn vertex(&mut self, p: [f64; 3]) -> u32 {
        self.pos.push(p);
        (self.pos.len() - 1) as u32
    }

    /// Replaces the faces with `faces` when the result is manifold; returns whether it did.
    fn try_faces(&mut self, faces: Vec<Vec<u32>>) -> bool {
        if !faces.is_empty() && is_manifold(&faces, self.pos.len()) {
            self.faces = faces;
            true
        } else {
            false
        }
    }

    /// Fan-triangulates every face from a random corner; `false` when that is not manifold.
    fn triangulate(&mut self, rng: &mut Rng) -> bool {
        let mut out = Vec::new();
        for f in &self.faces {
            let n = f.len();
            let s = rng.below(n);
            for k in 1..n - 1 {
                out.push(vec![f[s], f[(s + k) % n], f[(s + k + 1) % n]]);
            }
        }
        self.try_faces(out)
    }
}

fn base_shape(rng: &mut Rng, loop_scheme: bool) -> Builder {
    let tri = loop_scheme || rng.chance(20);
    match rng.below(10) {
        0..=2 => grid(rng, tri),
        3 | 4 => tube(rng, tri),
        5 => torus(rng, tri),
        _ => pole(rng, loop_scheme),
    }
}

/// An open `w` x `h` grid, quads or triangles.
fn grid(rng: &mut Rng, tri: bool) -> Builder {
    let (w, h) = (rng.range(1, 5) as u32, rng.range(1, 5) as u32);
    let g = subdiv_test_support::grid(w, h, tri, |i, j| {
        [i as f64, j as f64, 0.4 * rng.unit() as f64]
    });
    Builder {
        pos: g.positions,
        faces: g.faces,
    }
}

fn push_quad(b: &mut Builder, q: [u32; 4], tri: bool) {
    if tri {
        b.faces.push(vec![q[0], q[1], q[2]]);
        b.faces.push(vec![q[0], q[2], q[3]]);
    } else {
        b.faces.push(q.to_vec());
    }
}

/// A cylinder of `nu` x `nv` quads (or triangles) around z; open, or closed by n-gon caps or
/// triangle-fan poles.
fn tube(rng: &mut Rng, tri: bool) -> Builder {
    let nu = rng.range(3, 20) as u32;
    let nv = rng.range(1, (24 / nu as i64).max(1)) as u32;
    let mut b = Builder::default();
    for j in 0..=nv {
        for i in 0..nu {
            let a = TAU * i as f64 / nu as f64;
            b.vertex([a.cos(), a.sin(), j as f64 * 0.8]);
        }
    }
    let id = |i: u32, j: u32| j * nu + i % nu;
    for j in 0..nv {
        for i in 0..nu {
            push_quad(
                &mut b,
                [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)],
                tri,
            );
        }
    }
    let caps = rng.below(3);
    for (j, z, flip) in [(0, -0.6, true), (nv, nv as f64 * 0.8 + 0.6, false)] {
        let ring: Vec<u32> = (0..nu).map(|i| id(i, j)).collect();
        match caps {
            0 => {}
            1 if nu <= 8 && !tri => {
                let mut f = ring.clone();
                if flip {
                    f.reverse();
                }
                b.faces.push(f);
            }
            _ => {
                let p = b.vertex([0.0, 0.0, z]);
                for i in 0..nu as usize {
                    let (r0, r1) = (ring[i], ring[(i + 1) % ring.len()]);
                    b.faces.push(if flip {
                        vec![p, r1, r0]
                    } else {
                        vec![p, r0, r1]
                    });
                }
            }
        }
    }
    b
}

/// A torus of `nu` x `nv` quads (or triangles).
fn torus(rng: &mut Rng, tri: bool) -> Builder {
    let nu = rng.range(3, 6) as u32;
    let nv = rng.range(3, 5) as u32;
    let mut b = Builder::default();
    for j in 0..nv {
        for i in 0..nu {
            let (u, v) = (TAU * i as f64 / nu as f64, TAU * j as f64 / nv as f64);
            let r = 2.0 + 0.8 * v.cos();
            b.vertex([r * u.cos(), r * u.sin(), 0.8 * v.sin()]);
        }
    }
    let id = |i: u32, j: u32| (j % nv) * nu + i % nu;
    for j in 0..nv {
        for i in 0..nu {
            push_quad(
                &mut b,
                [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)],
                tri,
            );
        }
    }
    b
}

/// A pole of valence 2..=20: a fan of quads or triangles around it, wrapped or open, or a
/// closed bipyramid.
fn pole(rng: &mut Rng, loop_scheme: bool) -> Builder {
    let k = if rng.chance(40) {
        rng.range(9, 20)
    } else {
        rng.range(2, 8)
    } as u32;
    let mut b = Builder::default();
    let c = b.vertex([0.0, 0.0, 0.5]);
    let ring: Vec<u32> = (0..k)
        .map(|i| {
            let a = TAU * i as f64 / k as f64;
            b.vertex([a.cos(), a.sin(), 0.0])
        })
        .collect();
    let wrapped = rng.chance(70);
    let spokes = if wrapped { k } else { k - 1 };
    if !loop_scheme && rng.chance(50) {
        // Quads (centre, ring i, mid i, ring i+1): the centre has valence k, even k = 2.
        for i in 0..spokes {
            let a = TAU * (i as f64 + 0.5) / k as f64;
            let m = b.vertex([1.7 * a.cos(), 1.7 * a.sin(), -0.3]);
            b.faces
                .push(vec![c, ring[i as usize], m, ring[((i + 1) % k) as usize]]);
        }
        return b;
    }
    let k = k.max(3);
    let ring: Vec<u32> = if ring.len() < 3 {
        (0..3)
            .map(|i| {
                let a = TAU * i as f64 / 3.0;
                b.vertex([a.cos(), a.sin(), 0.0])
            })
            .collect()
    } else {
        ring
    };
    for i in 0..spokes.max(2) {
        b.faces
            .push(vec![c, ring[i as usize], ring[((i + 1) % k) as usize]]);
    }
    if wrapped && rng.chance(40) {
        let d = b.vertex([0.0, 0.0, -0.7]);
        for i in 0..k {
            b.faces
                .push(vec![d, ring[((i + 1) % k) as usize], ring[i as usize]]);
        }
    }
    b
}

/// Random topology steps, each kept only when the cage stays manifold.
fn mutate(rng: &mut Rng, b: &mut Builder, loop_scheme: bool) {
    let steps = rng.below(7);
    for _ in 0..steps {
        let n = b.faces.len();
        if n == 0 {
            return;
        }
        let f = rng.below(n);
        let mut faces = b.faces.clone();
        match rng.below(if loop_scheme { 3 } else { 5 }) {
            0 => {
                // Remove a face (a boundary or a bigger one).
                if n > 1 {
                    faces.remove(f);
                }
            }
            1 => split_diagonal(rng, &mut faces, f),
            2 => merge(rng, &mut faces, f),
            3 => {
                if !split_edge(rng, b, &mut faces, f) {
                    continue;
                }
            }
            _ => {
                // A quad split into two triangles.
                if faces[f].len() == 4 {
                    let q = faces.remove(f);
                    let s = rng.below(2);
                    faces.push(vec![q[s], q[s + 1], q[(s + 2) % 4]]);
                    faces.push(vec![q[s], q[(s + 2) % 4], q[(s + 3) % 4]]);
                }
            }
        }
        b.try_faces(faces);
    }
}

/// Splits face `f` (4 or more sides) along a random diagonal.
fn split_diagonal(rng: &mut Rng, faces: &mut Vec<Vec<u32>>, f: usize) {
    let n = faces[f].len();
    if n < 4 {
        return;
    }
    let i = rng.below(n);
    let j = (i + 2 + rng.below(n - 3)) % n;
    let g = faces.remove(f);
    let (a, c) = (i.min(j), i.max(j));
    faces.push(g[a..=c].to_vec());
    let mut rest = g[c..].to_vec();
    rest.extend_from_slice(&g[..=a]);
    faces.push(rest);
}

/// Merges face `f` with a neighbour across a random edge into one face of at most 8 sides.
fn merge(rng: &mut Rng, faces: &mut Vec<Vec<u32>>, f: usize) {
    let n = faces[f].len();
    let k = rng.below(n);
    let (a, b) = (faces[f][k], faces[f][(k + 1) % n]);
    let Some(g) = (0..faces.len()).find(|&g| {
        let m = faces[g].len();
        g != f && (0..m).any(|i| faces[g][i] == b && faces[g][(i + 1) % m] == a)
    }) else {
        return;
    };
    if n + faces[g].len() - 2 > 8 {
        return;
    }
    // f: ... a b ...   g: ... b a ...  merged: f from b round to a, then g from a round to b
    // (without repeating a and b).
    let fv = &faces[f];
    let gv = &faces[g];
    let m = gv.len();
    let ga = gv.iter().position(|&v| v == a).expect("a is in g");
    let mut merged: Vec<u32> = (0..n).map(|i| fv[(k + 1 + i) % n]).collect();
    merged.extend((1..m - 1).map(|i| gv[(ga + i) % m]));
    let (hi, lo) = (f.max(g), f.min(g));
    faces.remove(hi);
    faces.remove(lo);
    faces.push(merged);
}

/// Splits a random edge of face `f` at a new vertex (in both faces on it) when every face on
/// it keeps at most 8 sides. Catmull-Clark only (it makes a triangle a quad).
fn split_edge(rng: &mut Rng, b: &mut Builder, faces: &mut [Vec<u32>], f: usize) -> bool {
    let n = faces[f].len();
    let k = rng.below(n);
    let (a, c) = (faces[f][k], faces[f][(k + 1) % n]);
    let on_edge = |g: &Vec<u32>| {
        let m = g.len();
        (0..m).find(|&i| {
            let (x, y) = (g[i], g[(i + 1) % m]);
            (x == a && y == c) || (x == c && y == a)
        })
    };
    if faces.iter().any(|g| on_edge(g).is_some() && g.len() >= 8) {
        return false;
    }
    let (pa, pc) = (b.pos[a as usize], b.pos[c as usize]);
    let bend = 0.2 * rng.unit() as f64;
    let mid = b.vertex([
        0.5 * (pa[0] + pc[0]) + bend,
        0.5 * (pa[1] + pc[1]) - bend,
        0.5 * (pa[2] + pc[2]) + bend,
    ]);
    for g in faces.iter_mut() {
        if let Some(i) = on_edge(g) {
            g.insert(i + 1, mid);
        }
    }
    true
}

/// Jitters, scales and rounds the positions to multiples of 2^-10.
fn jitter(rng: &mut Rng, cage: &mut OsdCage) {
    let amp = 0.15 * rng.range(0, 4) as f64 / 4.0;
    let scale = [0.5, 1.0, 2.0, 7.0][rng.below(4)];
    let offset: [f64; 3] = std::array::from_fn(|_| rng.range(-4, 4) as f64 * 0.5);
    for p in &mut cage.positions {
        for (k, x) in p.iter_mut().enumerate() {
            let v = (*x + amp * rng.unit() as f64 + offset[k]) * scale;
            *x = (v * 1024.0).round() / 1024.0;
        }
    }
}

/// A sharpness: infinite (10), an integer or a fraction (multiple of 1/8) up to `max_semi`.
fn sharpness(rng: &mut Rng, max_semi: u32) -> f32 {
    match rng.below(10) {
        0 | 1 => 10.0,
        2..=4 => rng.range(1, max_semi as i64) as f32,
        _ => rng.range(1, 8 * max_semi as i64 - 1) as f32 / 8.0,
    }
}

/// Holes, creases, corners and options. Semi-sharp values stay small on bigger cages so that
/// OpenSubdiv's exact limit (level N + ceil(sharpness)) stays cheap.
fn add_tags(rng: &mut Rng, cage: &mut OsdCage) {
    let nf = cage.faces.len();
    let max_semi = match nf {
        0..=8 => 3,
        9..=20 => 2,
        _ => 1,
    };
    if nf >= 3 && rng.chance(20) {
        let mut holes: Vec<u32> = (0..1 + rng.below(nf / 3))
            .map(|_| rng.below(nf) as u32)
            .collect();
        holes.sort_unstable();
        holes.dedup();
        cage.holes = holes;
    }
    let edges = cage.edges();
    if rng.chance(65) {
        for _ in 0..1 + rng.below(5.min(edges.len())) {
            let (a, b) = edges[rng.below(edges.len())];
            if !cage.creases.iter().any(|c| (c.0, c.1) == (a, b)) {
                let s = sharpness(rng, max_semi);
                cage.creases.push((a, b, s));
            }
        }
    }
    if rng.chance(35) {
        for _ in 0..1 + rng.below(3) {
            let v = rng.below(cage.positions.len()) as u32;
            if !cage.corners.iter().any(|c| c.0 == v) {
                let s = sharpness(rng, max_semi);
                cage.corners.push((v, s));
            }
        }
    }
    if rng.chance(70) {
        cage.boundary = Some(rng.below(3) as u8);
    }
    if rng.chance(60) {
        cage.chaikin = Some(rng.chance(50));
    }
    if !cage.loop_scheme && rng.chance(60) {
        cage.smooth_triangles = Some(rng.chance(50));
    }
}

pub mod boundary_none;
mod nonmanifold;
pub use nonmanifold::NONMANIFOLD_PERCENT;
use nonmanifold::add_nonmanifold;
#[cfg(test)]
mod tests;
