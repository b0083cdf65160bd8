//! What the pixel-error mode measures once per cage ([`subdiv_depth::PatchErrors`]): for every
//! cage face and depth, how far the triangles drawn at that depth stray from the limit surface
//! and how far the normals interpolated across them turn from the limit normals, and a cone
//! bounding the face's limit normals.

use std::cell::RefCell;

use glam::Vec3;
use rayon::prelude::*;
use subdiv_depth::{NormalCone, PatchError, PatchErrors};
use subdiv_mesh::{FaceId, Mesh};
use subdiv_slate::{Depth, MAX_DEPTH, thread_worker};
use subdiv_stitch::Assembler;

/// Levels beyond the deepest drawn depth at which the limit surface is sampled: at `+2` every
/// drawn quad of the deepest depth holds a 5 × 5 grid of samples (corners, edge quarter points,
/// the points around its triangles' centroids), enough to find the worst point of a smooth
/// patch's deviation from its two triangles.
pub const SAMPLE_LEVELS: Depth = 2;

/// Which quantile of a patch's samples the normal error reports: 0.99, as `subdiv bench
/// quality`'s `shading_deg_p99` pools pixels. The largest angle would be the wrong statistic:
/// along a semi-sharp crease the limit normal turns by up to 70° across a strip about
/// `2^-s` of a face wide (the pawn's creases of sharpness 6), which no drawn depth up to 5 resolves (45° left
/// at depth 5) and which covers a negligible share of the pixels; bounding the maximum sent
/// 216 of the pawn's 588 faces to depth 5 at any tolerance under 10°.
pub const NORMAL_QUANTILE: f32 = 0.99;

/// Measures, for each cage face and depth `l <= max_depth`, the largest distance between the
/// limit surface and the triangles drawn at depth `l` and the [`NORMAL_QUANTILE`] of the angle
/// between limit and interpolated normals (each grid quad split along its
/// `(i, j)`–`(i + 1, j + 1)` diagonal, as `subdiv-stitch` draws it; the gap along the limit
/// normal, or the whole gap near the cage's boundary and holes, see `Grid::triangle_deviation`),
/// sampled on the depth
/// `max_depth + SAMPLE_LEVELS` grid (at most [`MAX_DEPTH`]) of every patch of the face; and a
/// cone containing the face's limit normals, widened by the largest angle between neighbouring
/// samples (normals between samples lean no further than that for a smooth patch).
pub fn patch_errors(mesh: &Mesh, asm: &Assembler, max_depth: Depth) -> PatchErrors {
    let set = asm.patch_set();
    let fine = (max_depth + SAMPLE_LEVELS).min(MAX_DEPTH);
    let per_patch: Vec<(Vec<f32>, Vec<f32>, NormalCone)> = set
        .patches()
        .par_iter()
        .map_init(
            || {
                let buffers = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
                (thread_worker(fine), buffers, RefCell::new(Vec::new()))
            },
            |(w, (pos, nrm, shade, sided), angles), p| {
                // Level-1 patches are one level coarser than their face.
                let l_fine = fine - p.level;
                let n = 1usize << l_fine;
                pos.resize((n + 1) * (n + 1), [0.0f32; 3]);
                nrm.resize((n + 1) * (n + 1), [0.0f32; 3]);
                w.patch_grid_sided(set.source(mesh, p), p.src_face, l_fine, pos, nrm, sided);
                // What the renderer shades this patch with: its own side's normal on creases.
                shade.clone_from(nrm);
                for &(k, q) in sided.iter() {
                    shade[k as usize] = q;
                }
                let grid = Grid { n, pos, nrm, shade };
                let outline = touches_outline(mesh, set.units()[p.unit as usize].face);
                let per_depth = |measure: &dyn Fn(Depth) -> f32| -> Vec<f32> {
                    (0..=max_depth)
                        .map(|ld| match ld.checked_sub(p.level) {
                            Some(l) if l <= l_fine => measure(l_fine - l),
                            _ => f32::INFINITY,
                        })
                        .collect()
                };
                let dev = per_depth(&|shift| grid.triangle_deviation(shift, outline));
                let turn =
                    per_depth(&|shift| grid.normal_deviation(shift, &mut angles.borrow_mut()));
                (dev, turn, grid.normal_cone())
            },
        )
        .collect();
    let mut faces = vec![
        PatchError {
            deviation: vec![0.0; max_depth as usize + 1],
            normal_error: vec![0.0; max_depth as usize + 1],
            normals: NormalCone::ANY,
        };
        mesh.num_faces()
    ];
    let mut cones: Vec<Vec<NormalCone>> = vec![Vec::new(); mesh.num_faces()];
    for (p, (dev, turn, cone)) in set.patches().iter().zip(per_patch) {
        let f = set.units()[p.unit as usize].face.idx();
        for (o, d) in faces[f].deviation.iter_mut().zip(dev) {
            *o = o.max(d);
        }
        for (o, a) in faces[f].normal_error.iter_mut().zip(turn) {
            *o = o.max(a);
        }
        cones[f].push(cone);
    }
    for (face, c) in faces.iter_mut().zip(&cones) {
        face.normals = merge_cones(c);
    }
    PatchErrors {
        faces,
        closed: is_closed(mesh),
    }
}

/// No boundary edges and no holes: hidden patches may stay at depth 0.
pub(crate) fn is_closed(mesh: &Mesh) -> bool {
    mesh.edges().all(|e| !mesh.is_boundary_edge(e)) && mesh.faces().all(|f| !mesh.is_hole(f))
}

/// Whether face `f` shares a vertex with the cage's boundary or with a hole (so the surface's
/// own edge may be an outline on screen near it).
pub(crate) fn touches_outline(mesh: &Mesh, f: FaceId) -> bool {
    mesh.face_vertices(f).iter().any(|&v| {
        mesh.outgoing(v).any(|h| {
            let g = mesh.face(h);
            !g.is_some() || mesh.is_hole(g) || !mesh.face(h.twin()).is_some()
        })
    })
}

/// One patch's limit points and normals on an `(n + 1)²` grid.
struct Grid<'a> {
    n: usize,
    pos: &'a [[f32; 3]],
    /// Limit normals (the mean of the sides' where the surface has a crease or a corner).
    nrm: &'a [[f32; 3]],
    /// The normals the renderer shades this patch with: `nrm`, except this patch's own side's
    /// normal at crease and corner points.
    shade: &'a [[f32; 3]],
}

impl Grid<'_> {
    #[inline]
    fn at(&self, i: usize, j: usize) -> Vec3 {
        Vec3::from(self.pos[j * (self.n + 1) + i])
    }

    /// Largest distance of a sample from the triangles of the coarser grid with `step` samples
    /// per quad side: quad `(a, b, c, e)` drawn as `(a, b, c)` and `(a, c, e)`, each sample
    /// against the triangle point of the same parameters. Inside the surface only the part of
    /// that gap along the limit normal counts: at a silhouette the normal lies across the line
    /// of sight, so the outline moves by the normal part, while the part along the surface
    /// slides points within it and moves nothing on screen. Where the face reaches the cage's
    /// boundary or a hole (`outline`), the surface's own edge is an outline too, and the whole
    /// gap counts.
    fn triangle_deviation(&self, shift: Depth, outline: bool) -> f32 {
        let step = 1usize << shift;
        let w = self.n + 1;
        let mut worst = 0.0f32;
        for j0 in (0..self.n).step_by(step) {
            for i0 in (0..self.n).step_by(step) {
                let a = self.at(i0, j0);
                let b = self.at(i0 + step, j0);
                let c = self.at(i0 + step, j0 + step);
                let e = self.at(i0, j0 + step);
                for j in j0..=j0 + step {
                    for i in i0..=i0 + step {
                        let u = (i - i0) as f32 / step as f32;
                        let v = (j - j0) as f32 / step as f32;
                        let on = if v <= u {
                            a * (1.0 - u) + b * (u - v) + c * v
                        } else {
                            a * (1.0 - v) + c * u + e * (v - u)
                        };
                        let gap = self.at(i, j) - on;
                        let d = if outline {
                            gap.length()
                        } else {
                            gap.dot(Vec3::from(self.nrm[j * w + i])).abs()
                        };
                        worst = worst.max(d);
                    }
                }
            }
        }
        worst
    }

    /// The [`NORMAL_QUANTILE`] of the angle (radians) between a sample's normal and the normal
    /// interpolated at its parameters across the coarser grid's triangles (as
    /// [`Grid::triangle_deviation`] splits the quads) from their corners' normals, the
    /// renderer's smooth shading, over the grid's samples; both normals from `shade`, so a
    /// crease's sides are compared with their own normals. `angles` is scratch space.
    fn normal_deviation(&self, shift: Depth, angles: &mut Vec<f32>) -> f32 {
        let step = 1usize << shift;
        let w = self.n + 1;
        let nrm = |i: usize, j: usize| Vec3::from(self.shade[j * w + i]);
        angles.clear();
        for j in 0..w {
            // The quad holding sample (i, j): the last row and column belong to the last quad.
            let j0 = (j / step * step).min(self.n - step);
            for i in 0..w {
                let i0 = (i / step * step).min(self.n - step);
                let a = nrm(i0, j0);
                let b = nrm(i0 + step, j0);
                let c = nrm(i0 + step, j0 + step);
                let e = nrm(i0, j0 + step);
                let u = (i - i0) as f32 / step as f32;
                let v = (j - j0) as f32 / step as f32;
                let on = if v <= u {
                    a * (1.0 - u) + b * (u - v) + c * v
                } else {
                    a * (1.0 - v) + c * u + e * (v - u)
                };
                let (m, t) = (on.normalize_or_zero(), nrm(i, j).normalize_or_zero());
                if m != Vec3::ZERO && t != Vec3::ZERO {
                    angles.push(m.dot(t).clamp(-1.0, 1.0).acos());
                }
            }
        }
        if angles.is_empty() {
            return 0.0;
        }
        let rank = ((NORMAL_QUANTILE * angles.len() as f32).ceil() as usize).clamp(1, angles.len());
        *angles.select_nth_unstable_by(rank - 1, f32::total_cmp).1
    }

    /// A cone around the grid's normals, widened by the largest angle between neighbours.
    fn normal_cone(&self) -> NormalCone {
        let w = self.n + 1;
        let normal = |k: usize| Vec3::from(self.nrm[k]);
        let mut margin = 0.0f32;
        for j in 0..w {
            for i in 0..w {
                let k = j * w + i;
                for m in [(i + 1 < w).then(|| k + 1), (j + 1 < w).then(|| k + w)]
                    .into_iter()
                    .flatten()
                {
                    let cos = normal(k).dot(normal(m)).clamp(-1.0, 1.0);
                    margin = margin.max(cos.acos());
                }
            }
        }
        NormalCone::bounding((0..w * w).map(normal), margin)
    }
}

/// A cone containing every given cone: around the normalised sum of their axes, as wide as the
/// farthest of them reaches.
fn merge_cones(cones: &[NormalCone]) -> NormalCone {
    if cones.iter().any(|c| c.cos <= -1.0) || cones.is_empty() {
        return NormalCone::ANY;
    }
    let axis = cones
        .iter()
        .map(|c| c.axis)
        .sum::<Vec3>()
        .normalize_or_zero();
    if axis == Vec3::ZERO {
        return NormalCone::ANY;
    }
    let half = cones
        .iter()
        .map(|c| axis.dot(c.axis).clamp(-1.0, 1.0).acos() + c.cos.clamp(-1.0, 1.0).acos())
        .fold(0.0f32, f32::max);
    if half >= std::f32::consts::PI {
        NormalCone::ANY
    } else {
        NormalCone {
            axis,
            cos: half.cos(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::parse_obj;

    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
                        f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

    #[test]
    fn deviations_fall_with_depth_and_match_a_dense_check() {
        let mesh = Mesh::from_soup(&parse_obj(CUBE).unwrap()).unwrap();
        let asm = Assembler::new(&mesh, 3).unwrap();
        let e = patch_errors(&mesh, &asm, 3);
        assert!(e.closed);
        for f in &e.faces {
            for l in 1..f.deviation.len() {
                assert!(f.deviation[l] < f.deviation[l - 1], "{:?}", f.deviation);
                // Interpolated normals turn less from the limit normals at every depth.
                let n = &f.normal_error;
                assert!(n[l] < n[l - 1], "{n:?}");
            }
            // Depth 0 of a cube face: the corner normals (54.7° off the face's axis)
            // interpolated across two triangles are a few degrees off somewhere (6.7°); three
            // levels down, about a degree.
            assert!(
                f.normal_error[0] > 3f32.to_radians(),
                "{:?}",
                f.normal_error
            );
            assert!(
                f.normal_error[3] < 2f32.to_radians(),
                "{:?}",
                f.normal_error
            );
            // A cube face's limit patch turns its normal by well under 90° but more than 10°.
            let half = f.normals.cos.acos().to_degrees();
            assert!(half > 10.0 && half < 90.0, "{half}");
        }
        // Depth-0 deviation of a cube face: its limit patch bulges from the chord quad by a
        // visible fraction of the edge; a sphere-like cube has deviation between 1 % and 30 %.
        let d0 = e.faces[0].deviation[0];
        assert!(d0 > 0.01 && d0 < 0.3, "{d0}");
    }

    #[test]
    fn open_meshes_are_not_closed_and_cones_merge() {
        let quad =
            Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap())
                .unwrap();
        let asm = Assembler::new(&quad, 2).unwrap();
        let e = patch_errors(&quad, &asm, 2);
        assert!(!e.closed);
        // A flat quad: the limit surface lies in the quad's plane; what remains is where its
        // outline leaves the chord triangles (a real gap on screen), falling with depth; the
        // normals are all +z.
        let d = &e.faces[0].deviation;
        assert!(d.windows(2).all(|w| w[1] < w[0]), "{d:?}");
        assert!((e.faces[0].normals.axis - Vec3::Z).length() < 1e-6);
        // Flat: interpolated normals are the limit normal.
        assert!(e.faces[0].normal_error.iter().all(|&a| a < 1e-3), "{e:?}");
        assert!(e.faces[0].normals.cos > 0.9999);
        let a = NormalCone {
            axis: Vec3::Z,
            cos: 10f32.to_radians().cos(),
        };
        let b = NormalCone {
            axis: Vec3::X,
            cos: 10f32.to_radians().cos(),
        };
        let m = merge_cones(&[a, b]);
        assert!((m.cos.acos().to_degrees() - 55.0).abs() < 0.01);
        assert_eq!(merge_cones(&[a, NormalCone::ANY]).cos, -1.0);
    }
}
