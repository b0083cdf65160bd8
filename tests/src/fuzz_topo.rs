//! Input fuzzing, part 2: topologies. Valid families (grids, closed polyhedra with n-gons, fans
//! up to valence 1000) and defective ones (an edge with three faces, bow-tie vertices, cones
//! touching at their tips, random soups), then cage-level mutations (flipped, duplicated or
//! dropped faces, bad indices, short faces, isolated vertices, degenerate or extreme positions).

use subdiv_test_support::Soup;

use crate::fuzz::{Cage, Rng};

/// A random topology and its family name.
pub fn topology(rng: &mut Rng) -> (Cage, &'static str) {
    match rng.below(9) {
        0 | 1 => (grid(rng), "grid"),
        2 => (prism(rng), "prism"),
        3 => (cube(), "cube"),
        4 => {
            let n = if rng.chance(10) {
                rng.range(100, 1000) as usize
            } else {
                rng.range(3, 12) as usize
            };
            let closed = rng.chance(50);
            (fan(rng, n, closed), "fan")
        }
        5 => (book(rng), "book"),
        6 => (bowtie(rng), "bowtie"),
        7 => (touching_cones(rng), "cones"),
        _ => (soup(rng), "soup"),
    }
}

fn p(x: f32, y: f32, z: f32) -> [f32; 3] {
    [x, y, z]
}

/// A `w` x `h` grid of quads (or triangles), open boundary.
fn grid(rng: &mut Rng) -> Cage {
    let (w, h) = (rng.range(1, 6), rng.range(1, 6));
    let tri = rng.chance(40);
    cage(subdiv_test_support::grid(
        w as u32,
        h as u32,
        tri,
        |i, j| p(i as f32, j as f32, 0.3 * rng.unit()),
    ))
}

/// The soup as a cage.
fn cage(s: Soup) -> Cage {
    Cage {
        pos: s.positions,
        faces: s
            .faces
            .iter()
            .map(|f| f.iter().map(|&v| v as i64).collect())
            .collect(),
    }
}

/// A closed prism over an n-gon: two n-gon caps and n quads.
fn prism(rng: &mut Rng) -> Cage {
    let n = rng.range(3, 9);
    let mut c = Cage::default();
    for z in [0.0, 1.0] {
        for k in 0..n {
            let a = k as f32 * std::f32::consts::TAU / n as f32;
            c.pos.push(p(a.cos(), a.sin(), z));
        }
    }
    c.faces.push((0..n).rev().collect());
    c.faces.push((n..2 * n).collect());
    for k in 0..n {
        let k1 = (k + 1) % n;
        c.faces.push(vec![k, k1, n + k1, n + k]);
    }
    c
}

/// The unit cube, outward-oriented quads.
pub fn cube() -> Cage {
    cage(subdiv_test_support::cube())
}

/// Valence `n`: a disk of triangles around vertex 0, closed into a bipyramid when `closed`.
fn fan(rng: &mut Rng, n: usize, closed: bool) -> Cage {
    let n = n as i64;
    let mut c = Cage::default();
    c.pos.push(p(0.0, 0.0, 1.0 + 0.1 * rng.unit()));
    for k in 0..n {
        let a = k as f32 * std::f32::consts::TAU / n as f32;
        c.pos.push(p(a.cos(), a.sin(), 0.0));
    }
    for k in 0..n {
        c.faces.push(vec![0, 1 + k, 1 + (k + 1) % n]);
    }
    if closed {
        c.pos.push(p(0.0, 0.0, -1.0));
        for k in 0..n {
            c.faces.push(vec![n + 1, 1 + (k + 1) % n, 1 + k]);
        }
    }
    c
}

/// Three (or more) triangles on one edge: a non-manifold edge.
fn book(rng: &mut Rng) -> Cage {
    let pages = rng.range(3, 5);
    let mut c = Cage::default();
    c.pos.push(p(0.0, 0.0, 0.0));
    c.pos.push(p(0.0, 0.0, 1.0));
    for k in 0..pages {
        let a = k as f32 * 2.0;
        c.pos.push(p(a.cos(), a.sin(), 0.5));
        let v = 2 + k;
        c.faces.push(if k % 2 == 0 || rng.chance(50) {
            vec![0, 1, v]
        } else {
            vec![1, 0, v]
        });
    }
    c
}

/// Two triangles (or quads) sharing only a vertex.
fn bowtie(rng: &mut Rng) -> Cage {
    let mut c = Cage::default();
    c.pos
        .extend([p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(1.0, 1.0, 0.0)]);
    c.pos.extend([p(-1.0, 0.0, 0.0), p(-1.0, -1.0, 0.0)]);
    c.faces.push(vec![0, 1, 2]);
    c.faces.push(vec![0, 3, 4]);
    if rng.chance(30) {
        c.pos.push(p(0.0, -1.0, 0.5));
        c.faces.push(vec![0, 4, 5]);
    }
    c
}

/// Two closed bipyramids sharing one apex: a non-manifold vertex with two closed fans.
fn touching_cones(rng: &mut Rng) -> Cage {
    let n = rng.range(3, 6);
    let mut a = fan(rng, n as usize, true);
    let b = fan(rng, n as usize, true);
    let off = a.pos.len() as i64 - 1;
    a.pos
        .extend(b.pos.iter().skip(1).map(|q| p(q[0] + 3.0, q[1], q[2])));
    for f in b.faces {
        a.faces.push(
            f.iter()
                .map(|&i| if i == 0 { 0 } else { i + off })
                .collect(),
        );
    }
    a
}

/// Random faces over a few vertices: anything goes.
fn soup(rng: &mut Rng) -> Cage {
    let nv = rng.range(0, 12);
    let mut c = Cage::default();
    for _ in 0..nv {
        c.pos.push(p(rng.unit(), rng.unit(), rng.unit()));
    }
    for _ in 0..rng.range(0, 10) {
        let len = rng.range(0, 6);
        c.faces.push((0..len).map(|_| rng.range(-1, nv)).collect());
    }
    c
}

/// Zero to three cage-level mutations.
pub fn mutate_cage(rng: &mut Rng, c: &mut Cage) {
    for _ in 0..rng.below(4) {
        mutate_once(rng, c);
    }
    if rng.chance(5) {
        scale_positions(rng, c);
    }
}

fn mutate_once(rng: &mut Rng, c: &mut Cage) {
    let nf = c.faces.len();
    let nv = c.pos.len() as i64;
    match rng.below(10) {
        0 if nf > 0 => c.faces[rng.below(nf)].reverse(),
        1 if nf > 0 => {
            let mut f = c.faces[rng.below(nf)].clone();
            if rng.chance(50) {
                f.reverse();
            }
            c.faces.push(f);
        }
        2 if nf > 0 => {
            c.faces.remove(rng.below(nf));
        }
        3 if nf > 0 => {
            let f = rng.below(nf);
            let k = rng.below(c.faces[f].len().max(1));
            let bad = *rng.pick(&[-1, nv, nv + 1, i64::MAX - 1, -(nv + 2), 0]);
            if let Some(x) = c.faces[f].get_mut(k) {
                *x = bad;
            }
        }
        4 if nf > 0 => {
            let f = rng.below(nf);
            let n = rng.below(3);
            c.faces[f].truncate(n);
        }
        5 if nf > 0 => {
            let f = rng.below(nf);
            if let Some(&x) = c.faces[f].first() {
                c.faces[f].push(x);
            }
        }
        6 => {
            for _ in 0..1 + rng.below(3) {
                c.pos.push([rng.unit(), rng.unit(), rng.unit()]);
            }
        }
        7 if nv > 1 => {
            let (a, b) = (rng.below(nv as usize), rng.below(nv as usize));
            c.pos[a] = c.pos[b];
        }
        8 if nv > 0 => {
            let bad = *rng.pick(&[f32::NAN, f32::INFINITY, -f32::INFINITY, f32::MAX, 1e-40]);
            let v = rng.below(nv as usize);
            c.pos[v][rng.below(3)] = bad;
        }
        _ => flatten(rng, c),
    }
}

/// Degenerate geometry: every vertex on a line, or all on one point.
fn flatten(rng: &mut Rng, c: &mut Cage) {
    let point = rng.chance(50);
    for (k, q) in c.pos.iter_mut().enumerate() {
        *q = if point {
            [0.5, 0.5, 0.5]
        } else {
            [k as f32, 0.0, 0.0]
        };
    }
}

/// Extreme but finite scales: tiny, huge, near `f32::MAX`.
fn scale_positions(rng: &mut Rng, c: &mut Cage) {
    let s = *rng.pick(&[1e-30f32, 1e-20, 1e15, 1e28, 1e29, 1e30, 1e37]);
    for q in &mut c.pos {
        for x in q.iter_mut() {
            *x *= s;
        }
    }
}
