//! The non-manifold cages of the generator: fins, tetrahedra on an edge,
//! bow-ties and fin strips, with the tags at a fin strip's middle vertex.

use super::Builder;
use crate::fuzz::Rng;

/// The share of cages (percent) made non-manifold by [`add_nonmanifold`].
pub const NONMANIFOLD_PERCENT: u64 = 15;

/// Makes a manifold cage non-manifold (as OpenSubdiv takes such cages): one or
/// two of a fin (one more face on an edge: three faces on an interior edge, two the same way
/// round on a boundary edge), a closed tetrahedron sharing an edge (four faces there), a
/// bow-tie (a pyramid, closed or open, touching the cage at one vertex), a fin strip (two fins
/// on consecutive edges of a face, sharing an edge from their common vertex: a vertex with
/// exactly two non-manifold edges, OpenSubdiv's crease rule along them). Triangles only for
/// Loop. Returns corner and crease tags for the cage: half the fin strips' middle vertices get a
/// semi-sharp vertex sharpness (a corner that turns into the crease after some levels), and
/// half of them (from `crease_rng`) semi-sharp creases on one or two of their edges that are
/// not non-manifold (the fins' shared edge, the cage's own): the whole vertex is a corner while
/// they last, whichever copies hold them.
pub(super) fn add_nonmanifold(
    rng: &mut Rng,
    crease_rng: &mut Rng,
    copy_rng: &mut Rng,
    b: &mut Builder,
    loop_scheme: bool,
) -> (Vec<(u32, f32)>, Vec<Crease>) {
    let (mut corners, mut creases) = (Vec::new(), Vec::new());
    for _ in 0..1 + rng.below(2) {
        let f = rng.below(b.faces.len());
        let n = b.faces[f].len();
        let k = rng.below(n);
        let (a, c) = (b.faces[f][k], b.faces[f][(k + 1) % n]);
        let (pa, pc) = (b.pos[a as usize], b.pos[c as usize]);
        let len = (0..3)
            .map(|i| (pc[i] - pa[i]).powi(2))
            .sum::<f64>()
            .sqrt()
            .max(0.25);
        let out = |rng: &mut Rng| -> [f64; 3] { std::array::from_fn(|_| len * rng.unit() as f64) };
        let off = |p: [f64; 3], d: [f64; 3]| [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
        match rng.below(4) {
            3 => {
                // A fin strip on a-c and c-d (consecutive edges of face f), the same way
                // round as f or the other, its two faces sharing the edge c-m.
                let d = b.faces[f][(k + 2) % n];
                let up = out(rng);
                let (x, y, z) = if rng.chance(50) { (a, c, d) } else { (d, c, a) };
                let m = b.vertex(off(b.pos[y as usize], up));
                if loop_scheme || rng.chance(30) {
                    b.faces.extend([vec![x, y, m], vec![y, z, m]]);
                } else {
                    let (mx, mz) = (
                        b.vertex(off(b.pos[x as usize], up)),
                        b.vertex(off(b.pos[z as usize], up)),
                    );
                    b.faces.extend([vec![x, y, m, mx], vec![y, z, mz, m]]);
                }
                if rng.chance(50) {
                    corners.push((c, rng.range(1, 18) as f32 / 8.0));
                }
                if crease_rng.chance(50) {
                    creases.extend(fin_strip_creases(crease_rng, &b.faces, c, [a, d, m]));
                }
                if copy_rng.chance(COPY_PERCENT) {
                    add_closed_fan(copy_rng, b, c, [a, d], len, loop_scheme);
                }
                if copy_rng.chance(COPY_PERCENT) {
                    add_cone_star(copy_rng, b, c, len);
                }
            }
            0 => {
                // A fin on a-c, either way round.
                let (x, y) = if rng.chance(50) { (a, c) } else { (c, a) };
                let up = out(rng);
                let (px, py) = (b.pos[x as usize], b.pos[y as usize]);
                if loop_scheme || rng.chance(30) {
                    let m = b.vertex(off(
                        [
                            0.5 * (px[0] + py[0]),
                            0.5 * (px[1] + py[1]),
                            0.5 * (px[2] + py[2]),
                        ],
                        up,
                    ));
                    b.faces.push(vec![x, y, m]);
                } else {
                    let (ny, nx) = (b.vertex(off(py, up)), b.vertex(off(px, up)));
                    b.faces.push(vec![x, y, ny, nx]);
                }
            }
            1 => {
                // A closed tetrahedron a, c, d, e sharing the edge a-c.
                let (d, e) = (b.vertex(off(pa, out(rng))), b.vertex(off(pc, out(rng))));
                b.faces
                    .extend([vec![a, c, d], vec![a, d, e], vec![a, e, c], vec![c, e, d]]);
            }
            _ => {
                // A pyramid with its apex at a: sides (a, d_{i+1}, d_i), the base closing it.
                let sides = if loop_scheme { 3 } else { 3 + rng.below(2) };
                let up = out(rng);
                let ring: Vec<u32> = (0..sides)
                    .map(|i| {
                        let t = std::f64::consts::TAU * i as f64 / sides as f64;
                        let r = 0.5 * len;
                        b.vertex(off(
                            pa,
                            [up[0] + r * t.cos(), up[1] + r * t.sin(), up[2] + 0.3 * r],
                        ))
                    })
                    .collect();
                for i in 0..sides {
                    b.faces.push(vec![a, ring[(i + 1) % sides], ring[i]]);
                }
                if rng.chance(70) {
                    b.faces.push(ring);
                }
            }
        }
    }
    (corners, creases)
}

/// The share of fin strips (percent) that get a closed fan at their middle vertex
/// ([`add_closed_fan`]).
const COPY_PERCENT: u64 = 25;

/// A fan of faces at the fin strip's middle vertex `c` whose copy holds neither or only one of
/// its two non-manifold edges `c-a`, `c-d` (`ends`): a closed tetrahedron touching `c`, a cone
/// of three triangles leaving and returning through one of the edges, or (Catmull-Clark) a
/// cube of quads touching `c` at a corner. The copy takes the crease rule over the edges of
/// one holding both (`Mesh::crease_ends`).
fn add_closed_fan(
    rng: &mut Rng,
    b: &mut Builder,
    c: u32,
    ends: [u32; 2],
    len: f64,
    loop_scheme: bool,
) {
    let pc = b.pos[c as usize];
    let twist: [f64; 3] = std::array::from_fn(|_| 0.2 * len * rng.unit() as f64);
    let at = |k: [f64; 3]| -> [f64; 3] { std::array::from_fn(|i| pc[i] + len * k[i] + twist[i]) };
    match rng.below(if loop_scheme { 2 } else { 3 }) {
        0 => {
            let t: Vec<u32> = [[1.0, 0.4, -1.0], [0.3, 1.0, -1.2], [-0.6, 0.2, -1.1]]
                .iter()
                .map(|&k| b.vertex(at(k)))
                .collect();
            b.faces.extend([
                vec![c, t[1], t[0]],
                vec![c, t[2], t[1]],
                vec![c, t[0], t[2]],
                vec![t[0], t[1], t[2]],
            ]);
        }
        1 => {
            let x = ends[rng.below(2)];
            let (p, q) = (
                b.vertex(at([0.6, 0.5, -1.0])),
                b.vertex(at([0.2, -0.4, -1.1])),
            );
            b.faces
                .extend([vec![c, x, p], vec![c, p, q], vec![c, q, x]]);
        }
        _ => {
            // Corners 1..8 of a unit cube, corner 0 at `c`.
            let cube = [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
                [0.0, 1.0, 1.0],
            ];
            let ids: Vec<u32> = cube
                .iter()
                .enumerate()
                .map(|(i, k)| {
                    if i == 0 {
                        c
                    } else {
                        b.vertex(at([k[0], k[1], -k[2] - 0.2]))
                    }
                })
                .collect();
            for f in [
                [0, 3, 2, 1],
                [4, 5, 6, 7],
                [0, 1, 5, 4],
                [2, 3, 7, 6],
                [0, 4, 7, 3],
                [1, 2, 6, 5],
            ] {
                b.faces.push(f.iter().map(|&k| ids[k]).collect());
            }
        }
    }
}

/// A component of its own beside vertex `c`: a vertex with exactly two non-manifold edges,
/// each made of two cones of three triangles that leave and return through it, so that no copy
/// of the vertex holds both (`Mesh::crease_ends` across copies).
fn add_cone_star(rng: &mut Rng, b: &mut Builder, c: u32, len: f64) {
    let pc = b.pos[c as usize];
    let at = |b: &mut Builder, rng: &mut Rng, k: [f64; 3]| -> u32 {
        let p: [f64; 3] = std::array::from_fn(|i| pc[i] + len * (k[i] + 0.15 * rng.unit() as f64));
        b.vertex(p)
    };
    let a = at(b, rng, [1.0, 0.0, 2.0]);
    let m = at(b, rng, [2.0, 0.0, 2.0]);
    let d = at(b, rng, [3.0, 0.0, 2.0]);
    for (x, dx) in [(a, 1.5), (d, 2.5)] {
        for side in [1.0, -1.0] {
            let p = at(b, rng, [dx, side, 2.0]);
            let q = at(b, rng, [dx, 0.5 * side, 2.0 + side]);
            b.faces
                .extend([vec![m, x, p], vec![m, p, q], vec![m, q, x]]);
        }
    }
}

/// A crease tag of an [`OsdCage`]: its two vertices and its sharpness.
type Crease = (u32, u32, f32);

/// One or two semi-sharp creases (multiples of 1/8 up to 2) on the edges at `c` other than
/// `skip` (the non-manifold edges' far ends), the first on the edge to the fins' apex
/// `skip[2]` or on an edge of the cage.
fn fin_strip_creases(rng: &mut Rng, faces: &[Vec<u32>], c: u32, skip: [u32; 3]) -> Vec<Crease> {
    let mut ends: Vec<u32> = faces
        .iter()
        .filter_map(|f| f.iter().position(|&v| v == c).map(|i| (f, i)))
        .flat_map(|(f, i)| [f[(i + 1) % f.len()], f[(i + f.len() - 1) % f.len()]])
        .filter(|&v| !skip[..2].contains(&v))
        .collect();
    ends.sort_unstable();
    ends.dedup();
    let mut out = Vec::new();
    for k in 0..1 + rng.below(2) {
        let to = if (k == 0 && rng.chance(50)) || ends.len() < 2 {
            skip[2]
        } else {
            ends[rng.below(ends.len())]
        };
        if ends.contains(&to) && !out.iter().any(|&(x, y, _)| x == to || y == to) {
            out.push((c.min(to), c.max(to), rng.range(1, 16) as f32 / 8.0));
        }
    }
    out
}
