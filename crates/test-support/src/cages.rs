//! Small cages as polygon soups: the unit cube, a triangular prism and grids, with their OBJ
//! text. Vertex and face orders are fixed: tests read face and vertex numbers off them.

use std::fmt::Write as _;

/// A polygon soup: positions and faces of 0-based vertex indices.
#[derive(Clone, Debug, PartialEq)]
pub struct Soup<P = [f32; 3]> {
    /// The vertex positions.
    pub positions: Vec<P>,
    /// The faces, 0-based indices into `positions`, counter-clockwise seen from outside.
    pub faces: Vec<Vec<u32>>,
}

impl Soup {
    /// The OBJ text: `v` lines, then `f` lines (1-based). Coordinates are written in the
    /// shortest form that reads back to the same `f32`.
    pub fn obj(&self) -> String {
        self.obj_grouped(&[])
    }

    /// [`Soup::obj`] with a `g NAME` line before face `first` for every `(first, NAME)`.
    pub fn obj_grouped(&self, groups: &[(usize, &str)]) -> String {
        let mut s = String::new();
        for p in &self.positions {
            writeln!(s, "v {} {} {}", p[0], p[1], p[2]).unwrap();
        }
        for (i, f) in self.faces.iter().enumerate() {
            for (_, name) in groups.iter().filter(|g| g.0 == i) {
                writeln!(s, "g {name}").unwrap();
            }
            s.push('f');
            for v in f {
                write!(s, " {}", v + 1).unwrap();
            }
            s.push('\n');
        }
        s
    }

    /// The soup with every face split into a fan of triangles around its first vertex
    /// (`a b c d` into `a b c`, `a c d`), in face order.
    pub fn triangulated(mut self) -> Soup {
        self.faces = self
            .faces
            .iter()
            .flat_map(|f| (1..f.len() - 1).map(|k| vec![f[0], f[k], f[k + 1]]))
            .collect();
        self
    }

    /// The soup with every position mapped by `f`.
    pub fn map_positions(mut self, f: impl FnMut([f32; 3]) -> [f32; 3]) -> Soup {
        self.positions = self.positions.into_iter().map(f).collect();
        self
    }
}

/// The unit cube `[0, 1]^3`: vertex `k` at `(k & 1, k >> 1 & 1, k >> 2 & 1)`; face 0 is
/// `z = 0`, face 1 `z = 1`, then `y = 0`, `y = 1`, `x = 0`, `x = 1` (closed, 6 quads).
pub fn cube() -> Soup {
    Soup {
        positions: (0..8)
            .map(|k| [(k & 1) as f32, ((k >> 1) & 1) as f32, ((k >> 2) & 1) as f32])
            .collect(),
        faces: vec![
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
        ],
    }
}

/// [`cube`]'s OBJ text in three groups: `bottom` (face 0), `top` (face 1) and `sides`.
pub fn grouped_cube_obj() -> String {
    cube().obj_grouped(&[(0, "bottom"), (1, "top"), (2, "sides")])
}

/// A closed triangular prism over the right triangle `(0,0) (1,0) (0,1)`, `z` in `[0, 1]`:
/// faces 0 and 1 are the triangles (bottom, top), faces 2..=4 the quads.
pub fn prism() -> Soup {
    Soup {
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],
        ],
        faces: vec![
            vec![0, 2, 1],
            vec![3, 4, 5],
            vec![0, 1, 4, 3],
            vec![0, 3, 5, 2],
            vec![1, 2, 5, 4],
        ],
    }
}

/// A `w` x `h` grid of cells: vertex `(i, j)` (row by row, `i` fastest) is `vertex(i, j)`;
/// cell `(i, j)` is the quad `(i, j) (i+1, j) (i+1, j+1) (i, j+1)`, or with `triangles` the
/// two triangles `(i, j) (i+1, j) (i+1, j+1)` and `(i, j) (i+1, j+1) (i, j+1)`.
pub fn grid<P>(w: u32, h: u32, triangles: bool, mut vertex: impl FnMut(u32, u32) -> P) -> Soup<P> {
    let mut positions = Vec::new();
    for j in 0..=h {
        for i in 0..=w {
            positions.push(vertex(i, j));
        }
    }
    let id = |i: u32, j: u32| j * (w + 1) + i;
    let mut faces = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if triangles {
                faces.push(vec![q[0], q[1], q[2]]);
                faces.push(vec![q[0], q[2], q[3]]);
            } else {
                faces.push(q.to_vec());
            }
        }
    }
    Soup { positions, faces }
}

/// An `n` x `n` [`grid`] of unit cells from `(origin, origin)` in the plane, vertex `(x, y)`
/// at height `height(x, y)`.
pub fn height_grid(n: u32, triangles: bool, origin: f32, height: impl Fn(f32, f32) -> f32) -> Soup {
    grid(n, n, triangles, |i, j| {
        let (x, y) = (i as f32 + origin, j as f32 + origin);
        [x, y, height(x, y)]
    })
}

/// `obj` (OBJ text) with every vertex line's position repeated as its colour (`v x y z x y z`,
/// the vertex primvar `displayColor`): a primvar that the positions' masks must carry to
/// exactly the surface's points. Colours already on the lines are replaced; other lines kept.
pub fn colours_from_positions(obj: &str) -> String {
    colours_from(obj, |p| p)
}

/// `obj` (OBJ text) with every vertex line's colour `f(position)` (the vertex primvar
/// `displayColor`); other lines kept. With an affine `f` the primvar's limit is `f` of the
/// surface's points (subdivision is affine invariant), with values unlike the positions.
pub fn colours_from(obj: &str, f: impl Fn([f64; 3]) -> [f64; 3]) -> String {
    obj.lines()
        .map(|l| match l.strip_prefix("v ") {
            Some(v) => {
                let xyz: Vec<&str> = v.split_whitespace().take(3).collect();
                let p = [0, 1, 2].map(|k| xyz[k].parse::<f64>().unwrap_or(0.0));
                let [r, g, b] = f(p);
                format!("v {} {r} {g} {b}\n", xyz.join(" "))
            }
            None => format!("{l}\n"),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_text_is_the_classic_unit_cube() {
        assert_eq!(
            cube().obj(),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n"
        );
    }

    #[test]
    fn triangulated_cube_splits_each_quad_at_its_first_vertex() {
        let t = cube().triangulated().obj();
        assert!(t.ends_with(
            "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\n\
             f 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n"
        ));
        assert!(grouped_cube_obj().contains("g top\nf 5 6 8 7\ng sides\nf 1 2 6 5\n"));
    }

    #[test]
    fn prism_text_and_groups() {
        let text = prism().obj_grouped(&[(0, "caps"), (2, "sides")]);
        assert_eq!(
            text,
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\n\
             g caps\nf 1 3 2\nf 4 5 6\ng sides\nf 1 2 5 4\nf 1 4 6 3\nf 2 3 6 5\n"
        );
    }

    #[test]
    fn grid_cells_and_triangles() {
        let q = grid(2, 1, false, |i, j| [i as f32, j as f32, 0.0]);
        assert_eq!(q.positions.len(), 6);
        assert_eq!(q.faces, [vec![0, 1, 4, 3], vec![1, 2, 5, 4]]);
        let t = grid(1, 1, true, |i, j| (i, j));
        assert_eq!(t.positions, [(0, 0), (1, 0), (0, 1), (1, 1)]);
        assert_eq!(t.faces, [vec![0, 1, 3], vec![0, 3, 2]]);
        let h = height_grid(2, false, -1.0, |x, y| x * y);
        assert_eq!(h.positions[0], [-1.0, -1.0, 1.0]);
        assert_eq!(h.positions[8], [1.0, 1.0, 1.0]);
        let c = cube().map_positions(|p| p.map(|x| 2.0 * x - 1.0));
        assert_eq!(c.positions[0], [-1.0; 3]);
        assert_eq!(c.positions[7], [1.0; 3]);
    }
}
