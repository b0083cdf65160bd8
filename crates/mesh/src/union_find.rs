//! Union-find (disjoint sets) over `0..n`: the one home of the forest that groups corners into
//! fans (the soup's non-manifold cut), faces into components (mesh statistics), corners into
//! sectors (sector normals) and the DoIs' level-set pieces (curve skeletons).

/// A union-find forest over the elements `0..n`, with path halving. Every set's root is its
/// smallest element ([`UnionFind::union`] hangs the larger root under the smaller), so the
/// labels [`UnionFind::find`] gives do not depend on the order of the unions.
///
/// ```
/// use subdiv_mesh::UnionFind;
/// let mut sets = UnionFind::new(5);
/// sets.union(3, 1);
/// sets.union(4, 3);
/// assert_eq!((sets.find(4), sets.find(1), sets.find(2)), (1, 1, 2));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    /// `n` singletons.
    pub fn new(n: usize) -> UnionFind {
        UnionFind {
            parent: (0..n).collect(),
        }
    }

    /// The root (smallest element) of `x`'s set, halving the path on the way.
    ///
    /// # Panics
    /// If `x` is not below the forest's size.
    #[inline]
    pub fn find(&mut self, mut x: usize) -> usize {
        let p = &mut self.parent;
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }

    /// Joins the sets of `a` and `b`; the new root is the smaller of their roots.
    ///
    /// # Panics
    /// If `a` or `b` is not below the forest's size.
    #[inline]
    pub fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        self.parent[ra.max(rb)] = ra.min(rb);
    }
}
