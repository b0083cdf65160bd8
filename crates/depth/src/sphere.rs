//! Bounding spheres of the limit patches (Settgast et al. 2004, Section 3.1: "We use a bounding
//! sphere around the considered patch and estimate the radius of the projected sphere onto the
//! image plane").
//!
//! **Why the sphere contains the limit patch.** Every Catmull-Clark rule this workspace applies
//! (`subdiv_rules::catmark`) is an affine combination with non-negative weights: the face point
//! is a centroid; the smooth edge point is `(a + b + f0 + f1) / 4`, the crease and boundary edge
//! point the midpoint, a semi-sharp edge a blend of the two with weight `w` in `[0, 1]`; the
//! smooth and dart vertex rule weighs the vertex `(n - 2) / n >= 0` (any valence `n >= 2`, so
//! extraordinary vertices too) and its edge and face points `1 / n^2`, the crease rule
//! `(1/8, 3/4, 1/8)`, the corner rule keeps the vertex, and fractional sharpness blends two
//! such rules with a weight in `[0, 1]`. The points of a face's children together with their
//! 1-neighbourhoods are computed from the face's own 1-neighbourhood only (the premise of the
//! paper's slates, Section 3), so by induction every control point of every descendant of a
//! face lies in the convex hull of the face's 1-neighbourhood control points. The limit patch
//! is the closure of the limit points of those descendants' vertices (limit masks are positive
//! too), so it lies in that closed convex hull, and a sphere that contains the hull's points
//! contains the hull (a ball is convex) and the patch.
//!
//! Loop (`subdiv_rules::loop_scheme`) is the same: the edge point weighs `(3/8, 3/8, 1/8, 1/8)`,
//! the smooth vertex rule `1 - n beta` and `beta` with `n beta <= 5/8` for every valence, the
//! crease, boundary and corner rules are Catmull-Clark's, and a triangle's children with their
//! 1-neighbourhoods come from the triangle's own 1-neighbourhood (the triangles sharing a vertex
//! with it, the premise of the triangular slates); its limit masks are positive too.
//! [`face_spheres`] applies the argument to either scheme.
//!
//! Applied `k` levels down, the same argument bounds the patch by the union of the
//! 1-neighbourhoods of its level-`k` descendants, which reaches only about `2^-k` of a face
//! beyond the face: a tight sphere that is still a proof. Positions are `f32`, so the radius
//! gets a rounding margin.

use glam::Vec3;
use subdiv_mesh::Mesh;
use subdiv_rules::{Depth, Scheme};

/// A bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub centre: Vec3,
    /// Radius.
    pub radius: f32,
}

/// Levels of local refinement behind the spheres: at level 2 the hull reaches a quarter of a
/// level-1 face (an eighth of the cage face's width) beyond the face, against a whole face
/// at level 0; a third level would gain another sixteenth for four times the work.
pub const SPHERE_LEVELS: Depth = 2;

/// Most faces the refinement behind the spheres may create (16 Mi faces, about 1 GiB of
/// mesh); larger cages use fewer levels, down to the cage's own 1-neighbourhoods.
pub const SPHERE_FACE_BUDGET: u64 = 1 << 24;

/// A sphere per cage face that provably contains the face's limit patch of `scheme` (a Loop
/// cage's triangles for [`Scheme::Loop`]; see the module documentation): the smallest sphere
/// around the centre of the bounding box of the control points of the 1-neighbourhoods of the
/// face's level-`k` descendants that contains them all, `k =` [`SPHERE_LEVELS`] (fewer for very
/// large cages). A cage that moves keeps a [`FaceSpheres`] instead.
pub fn face_spheres(mesh: &Mesh, scheme: Scheme) -> Vec<Sphere> {
    FaceSpheres::new(mesh, scheme).spheres
}

/// [`face_spheres`] for a cage whose positions change while its topology stays (an animated
/// character): the refinement's meshes and each face's set of hull points are kept, and
/// [`FaceSpheres::move_to`] only refines the new positions through them and takes the
/// spheres, the same bits as [`face_spheres`] of the moved cage.
#[derive(Clone, Debug)]
pub struct FaceSpheres {
    scheme: Scheme,
    /// Levels `1..=k` of the uniform refinement, with the last positions (empty: the cage's own
    /// 1-neighbourhoods bound its faces).
    levels: Vec<Mesh>,
    /// Per cage face `a`, the finest level's vertices whose positions bound it:
    /// `hull[hull_at[a]..hull_at[a + 1]]`, ascending.
    hull_at: Vec<u32>,
    hull: Vec<u32>,
    spheres: Vec<Sphere>,
}

impl FaceSpheres {
    /// The refinement of `mesh` behind its spheres, and the spheres.
    pub fn new(mesh: &Mesh, scheme: Scheme) -> FaceSpheres {
        let mut levels = Vec::new();
        let k = (1..=SPHERE_LEVELS).rev().find(|&k| {
            if subdiv_rules::refined_face_count(mesh, scheme, k) > SPHERE_FACE_BUDGET {
                return false;
            }
            // `refine_uniform_levels`'s checks and refinement, keeping each level.
            levels.clear();
            let request = subdiv_rules::Request::Uniform { scheme, depth: k };
            if subdiv_rules::check_coordinates(mesh).is_err()
                || subdiv_rules::Budget::machine()
                    .check(mesh, request)
                    .is_err()
            {
                return false;
            }
            for _ in 0..k {
                match subdiv_rules::refine_uniform(levels.last().unwrap_or(mesh), scheme) {
                    Ok(fine) => levels.push(fine),
                    Err(_) => return false,
                }
            }
            true
        });
        let (hull_at, hull) = match k {
            Some(k) => hull_sets(
                &levels[levels.len() - 1],
                &ancestors(mesh, k, scheme),
                mesh.num_faces(),
            ),
            None => {
                levels.clear();
                let identity: Vec<u32> = (0..mesh.num_faces() as u32).collect();
                hull_sets(mesh, &identity, mesh.num_faces())
            }
        };
        let spheres = match levels.last() {
            Some(fine) => spheres_of(fine.positions(), &hull_at, &hull),
            None => spheres_of(mesh.positions(), &hull_at, &hull),
        };
        FaceSpheres {
            scheme,
            levels,
            hull_at,
            hull,
            spheres,
        }
    }

    /// The spheres of the cage's last positions.
    pub fn spheres(&self) -> &[Sphere] {
        &self.spheres
    }

    /// The spheres of `mesh`, the cage with other positions (the same topology and tags as
    /// the one this was made for). A cage beyond the coordinates the refinement takes is
    /// bounded by its own 1-neighbourhoods, as [`face_spheres`] bounds it.
    pub fn move_to(&mut self, mesh: &Mesh) -> &[Sphere] {
        if self.levels.is_empty() || subdiv_rules::check_coordinates(mesh).is_err() {
            *self = FaceSpheres::new(mesh, self.scheme);
            return &self.spheres;
        }
        for i in 0..self.levels.len() {
            let (coarser, finer) = self.levels.split_at_mut(i);
            let coarse = coarser.last().unwrap_or(mesh);
            let fp: Vec<Vec3> = if self.scheme.splits_to_quads() {
                coarse.faces().map(|f| coarse.face_centroid(f)).collect()
            } else {
                Vec::new()
            };
            let points = subdiv_rules::RefineKernel::new(coarse, self.scheme).refine_points(&fp);
            finer[0].positions_mut().copy_from_slice(&points);
        }
        let fine = &self.levels[self.levels.len() - 1];
        self.spheres = spheres_of(fine.positions(), &self.hull_at, &self.hull);
        &self.spheres
    }
}

/// The cage face of every face of the level-`k` uniform refinement (`subdiv_rules::refine`
/// numbers the children of each face consecutively: Catmull-Clark `n` for an n-gon, then 4 per
/// quad; Loop 4 per triangle).
fn ancestors(mesh: &Mesh, k: Depth, scheme: Scheme) -> Vec<u32> {
    let children = |f| match scheme {
        Scheme::CatmullClark | Scheme::Bilinear => mesh.face_size(f),
        Scheme::Loop => 4,
    };
    let mut anc: Vec<u32> = mesh
        .faces()
        .flat_map(|f| std::iter::repeat_n(f.0, children(f)))
        .collect();
    for _ in 1..k {
        anc = anc.iter().flat_map(|&a| [a; 4]).collect();
    }
    anc
}

/// Per ancestor, all vertices of the fine faces that share a vertex with one of its
/// descendants (`ancestor[g]` is the cage face of fine face `g`): each descendant's
/// 1-neighbourhood, as offsets into a list of vertices (ascending per ancestor).
fn hull_sets(fine: &Mesh, ancestor: &[u32], n: usize) -> (Vec<u32>, Vec<u32>) {
    // Ancestors whose descendants touch each fine vertex.
    let mut touching: Vec<Vec<u32>> = vec![Vec::new(); fine.num_vertices()];
    for g in fine.faces() {
        let a = ancestor[g.idx()];
        for v in fine.face_vertices(g) {
            let t = &mut touching[v.idx()];
            if !t.contains(&a) {
                t.push(a);
            }
        }
    }
    // Every fine face touching a descendant of `a` at a vertex is in that descendant's
    // 1-neighbourhood: its points are in `a`'s hull set.
    let mut sets: Vec<Vec<u32>> = vec![Vec::new(); n];
    for g in fine.faces() {
        let vs = fine.face_vertices(g);
        for v in vs {
            for &a in &touching[v.idx()] {
                sets[a as usize].extend(vs.iter().map(|w| w.0));
            }
        }
    }
    let mut hull_at = Vec::with_capacity(n + 1);
    let mut hull = Vec::new();
    hull_at.push(0);
    for mut set in sets {
        set.sort_unstable();
        set.dedup();
        hull.extend_from_slice(&set);
        hull_at.push(hull.len() as u32);
    }
    (hull_at, hull)
}

/// The sphere of each ancestor's hull set ([`hull_sets`]) at `positions`: around the centre of
/// the set's bounding box, through its farthest point, with a rounding margin.
fn spheres_of(positions: &[Vec3], hull_at: &[u32], hull: &[u32]) -> Vec<Sphere> {
    hull_at
        .windows(2)
        .map(|w| {
            let set = &hull[w[0] as usize..w[1] as usize];
            let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            for &v in set {
                let p = positions[v as usize];
                lo = lo.min(p);
                hi = hi.max(p);
            }
            let c = (lo + hi) * 0.5;
            let r2 = set
                .iter()
                .map(|&v| (positions[v as usize] - c).length_squared())
                .fold(0.0f32, f32::max);
            let r = r2.sqrt();
            // Rounding: the refined points carry a few ulps of error per level.
            let margin = 16.0 * f32::EPSILON * (c.abs().max_element() + r);
            Sphere {
                centre: if c.is_finite() { c } else { Vec3::ZERO },
                radius: r + margin,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::parse_obj;
    use subdiv_rules::tessellate_uniform;

    /// Every limit point of a fine uniform tessellation lies in its cage face's sphere.
    fn assert_contains(mesh: &Mesh, spheres: &[Sphere], depth: Depth) {
        assert_contains_scheme(mesh, spheres, depth, Scheme::CatmullClark);
    }

    fn assert_contains_scheme(mesh: &Mesh, spheres: &[Sphere], depth: Depth, scheme: Scheme) {
        let lim = tessellate_uniform(mesh, scheme, depth).unwrap();
        let anc = ancestors(mesh, depth, scheme);
        for (g, a) in anc.iter().enumerate() {
            let s = spheres[*a as usize];
            for &v in lim.face(g) {
                let p = Vec3::from(lim.positions()[v as usize]);
                let d = (p - s.centre).length();
                assert!(
                    d <= s.radius,
                    "face {a}: limit point at {d} > radius {}",
                    s.radius
                );
            }
        }
    }

    #[test]
    fn spheres_contain_the_limit_surface() {
        let cube =
            Mesh::from_soup(&parse_obj(&subdiv_test_support::cube().obj()).unwrap()).unwrap();
        let s = face_spheres(&cube, Scheme::CatmullClark);
        assert_contains(&cube, &s, 4);
        // Tight: well inside the unit cube's face circle grown by its 1-ring (radius 1.5).
        assert!(s.iter().all(|s| s.radius < 0.75), "{s:?}");
        // A crease and an extraordinary vertex (a pentagon fan) keep the property.
        let pent = "v 0 0 0\nv 1 0 0\nv 0.3 0.95 0\nv -0.8 0.6 0.2\nv -0.8 -0.6 0\nv 0.3 -0.95 0.3\n\
                    v 2 1 0\nv 2 -1 0\n\
                    f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 6\nf 1 6 2\nf 2 8 7 3\nf 2 6 8\n\
                    t crease 2/1/0 0 1 1.5\nt crease 2/1/0 0 4 5\n";
        let m = Mesh::from_soup(&parse_obj(pent).unwrap()).unwrap();
        let s = face_spheres(&m, Scheme::CatmullClark);
        assert_contains(&m, &s, 4);
    }

    #[test]
    fn loop_spheres_contain_the_loop_limit_surface() {
        // Every Loop fixture (creases, semi-sharp creases, boundaries, corners, high valence).
        let dir = subdiv_test_support::fixture("reference/shapes");
        let mut seen = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            if !(name.starts_with("loop_") && name.ends_with(".obj")) {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let m = Mesh::from_soup(&parse_obj(&text).unwrap()).unwrap();
            let s = face_spheres(&m, Scheme::Loop);
            assert_contains_scheme(&m, &s, 4, Scheme::Loop);
            seen += 1;
        }
        assert!(seen >= 9, "{seen} loop fixtures");
    }

    #[test]
    fn level_zero_hull_is_looser_but_contains() {
        let cube =
            Mesh::from_soup(&parse_obj(&subdiv_test_support::cube().obj()).unwrap()).unwrap();
        let identity: Vec<u32> = (0..6).collect();
        let (at, hull) = hull_sets(&cube, &identity, 6);
        let coarse = spheres_of(cube.positions(), &at, &hull);
        assert_contains(&cube, &coarse, 4);
        let fine = face_spheres(&cube, Scheme::CatmullClark);
        assert!(coarse.iter().zip(&fine).all(|(c, f)| f.radius < c.radius));
    }

    #[test]
    fn a_moved_cage_has_the_spheres_made_afresh_for_it() {
        // Catmull-Clark and Loop fixtures (n-gons, creases, semi-sharp creases, boundaries),
        // each moved three times: the kept refinement gives the bits of a fresh one.
        let mut seen = 0;
        for name in [
            "catmark_pawn.obj",
            "catmark_nonquads.obj",
            "catmark_cube_creases1.obj",
            "catmark_helmet.obj",
            "catmark_chaikin0.obj",
            "loop_cubes_semisharp.obj",
            "loop_saddle_edgecorner.obj",
        ] {
            let scheme = match name.starts_with("loop") {
                true => Scheme::Loop,
                false => Scheme::CatmullClark,
            };
            let text = std::fs::read_to_string(subdiv_test_support::shape(name)).unwrap();
            let mut m = Mesh::from_soup(&parse_obj(&text).unwrap()).unwrap();
            let mut kept = FaceSpheres::new(&m, scheme);
            assert!(!kept.levels.is_empty(), "{name}");
            for step in 1..=3 {
                for (i, p) in m.positions_mut().iter_mut().enumerate() {
                    let t = step as f32 * 0.37 + i as f32 * 0.11;
                    *p += Vec3::new(t.sin(), (1.3 * t).cos(), 0.5 * t.sin() * p.x) * 0.1;
                }
                let afresh = face_spheres(&m, scheme);
                assert!(kept.move_to(&m) == afresh.as_slice(), "{name} step {step}");
            }
            seen += 1;
        }
        assert_eq!(seen, 7);
    }
}
