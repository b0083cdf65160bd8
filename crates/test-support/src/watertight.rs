//! The watertightness check of a triangle list: weld the vertices whose positions are equal,
//! then count directed edges. On a crack-free surface every directed edge is used once and,
//! away from the boundary, its reverse once too.

use std::collections::HashMap;

/// Per vertex, the id of the first vertex with a bitwise equal position (ids count the
/// distinct positions in order of first use).
pub fn weld(positions: &[[f32; 3]]) -> Vec<u32> {
    weld_by(positions, |p| p.map(f32::to_bits))
}

/// [`weld`] by value rather than by bits: `0.0` and `-0.0` are one coordinate.
pub fn weld_values(positions: &[[f32; 3]]) -> Vec<u32> {
    weld_by(positions, |p| {
        p.map(|x| if x == 0.0 { 0 } else { x.to_bits() })
    })
}

fn weld_by(positions: &[[f32; 3]], key: impl Fn([f32; 3]) -> [u32; 3]) -> Vec<u32> {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    positions
        .iter()
        .map(|&p| {
            let n = ids.len() as u32;
            *ids.entry(key(p)).or_insert(n)
        })
        .collect()
}

/// Counts the directed edges of the triangles `indices` (three a triangle) with vertex ids
/// `id`; panics (naming `name`) on a degenerate triangle or on a directed edge used twice.
/// Returns the open edges: directed edges whose reverse is not used.
pub fn open_edges_by(name: &str, indices: &[u32], id: impl Fn(u32) -> u32) -> usize {
    assert_eq!(indices.len() % 3, 0, "{name}: not a triangle list");
    let mut dir: HashMap<(u32, u32), u32> = HashMap::new();
    for t in indices.chunks(3) {
        let t = [id(t[0]), id(t[1]), id(t[2])];
        assert!(
            t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
            "{name}: degenerate triangle {t:?}"
        );
        for k in 0..3 {
            *dir.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    for (&(a, b), &c) in &dir {
        assert_eq!(c, 1, "{name}: directed edge {a}->{b} used {c} times");
    }
    dir.keys()
        .filter(|&&(a, b)| !dir.contains_key(&(b, a)))
        .count()
}

/// [`open_edges_by`] on the vertex indices themselves.
pub fn indexed_open_edges(name: &str, indices: &[u32]) -> usize {
    open_edges_by(name, indices, |i| i)
}

/// [`open_edges_by`] after welding bitwise equal positions ([`weld`]): a T-junction or a flip
/// between two pieces shows as a directed edge used twice or an open edge.
pub fn welded_open_edges(name: &str, positions: &[[f32; 3]], indices: &[u32]) -> usize {
    let id = weld(positions);
    open_edges_by(name, indices, |i| id[i as usize])
}

/// The open edges by index and after welding, which must agree (points at one position are
/// one vertex); panics as [`open_edges_by`] does. Returns the open edges.
pub fn open_edges(name: &str, positions: &[[f32; 3]], indices: &[u32]) -> usize {
    let welded = welded_open_edges(name, positions, indices);
    assert_eq!(
        welded,
        indexed_open_edges(name, indices),
        "{name}: open edges by position vs. by index"
    );
    welded
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles of a unit square, the second with its own copy of the shared corners.
    fn split_square() -> (Vec<[f32; 3]>, Vec<u32>) {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        (p, vec![0, 1, 2, 3, 4, 5])
    }

    #[test]
    fn welding_closes_the_seam_that_indices_leave_open() {
        let (p, t) = split_square();
        assert_eq!(weld(&p), [0, 1, 2, 0, 2, 3]);
        assert_eq!(indexed_open_edges("square", &t), 6);
        assert_eq!(welded_open_edges("square", &p, &t), 4);
    }

    #[test]
    #[should_panic(expected = "by position vs. by index")]
    fn open_edges_wants_shared_points_shared() {
        let (p, t) = split_square();
        open_edges("square", &p, &t);
    }

    #[test]
    #[should_panic(expected = "used 2 times")]
    fn a_flipped_neighbour_is_a_directed_edge_used_twice() {
        indexed_open_edges("flip", &[0, 1, 2, 0, 1, 3]);
    }

    #[test]
    fn signed_zeros_weld_by_value_only() {
        let p = [[0.0, 0.0, 0.0], [-0.0, 0.0, 0.0]];
        assert_eq!(weld(&p), [0, 1]);
        assert_eq!(weld_values(&p), [0, 0]);
    }
}
