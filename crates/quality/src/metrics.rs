//! Image error of a rendered tessellation against a reference render: silhouette distance in
//! pixels and shading angle in degrees.
//!
//! - **Silhouette.** Coverage masks of candidate and reference are compared pixel by pixel; for
//!   every pixel where they disagree the error is the Euclidean distance from its centre to the
//!   reference silhouette, taken as the midpoints of the edges between a covered and an
//!   uncovered cell of the reference (so a pixel wrongly covered right next to the silhouette
//!   counts 0.5 px, one a pixel further 1.5 px). Distances are exact (Felzenszwalb &
//!   Huttenlocher's linear-time Euclidean distance transform on a grid of half cells). The
//!   cells are pixels in [`compare_frames`]; a quality run locates the reference silhouette
//!   among its supersamples ([`sample_silhouette_distance`]): a sheet seen edge on that is
//!   thinner than the area-coverage threshold is absent from the reference's pixel mask, and a
//!   candidate pixel covering it would otherwise count as far from a silhouette that in truth
//!   runs through that very pixel.
//! - **Shading.** Inside both masks, the angle between the candidate's and the reference's
//!   interpolated unit normals; also over the pixels off the reference's *lines*
//!   ([`super::lines::line_pixels`]: where the true normal turns by more than the tolerance from one pixel to
//!   the next, crease lines and folds that no tessellation resolves at pixel scale).

/// Errors of one rendered frame against its reference.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameErrors {
    /// Per disagreeing pixel: distance to the reference silhouette, in pixels.
    pub silhouette_px: Vec<f32>,
    /// Per pixel covered in both: normal angle in degrees.
    pub shading_deg: Vec<f32>,
    /// The angles of `shading_deg` at the pixels that are not line pixels of the reference.
    pub shading_deg_off_lines: Vec<f32>,
}

/// The `q`-quantile (0..=1, nearest rank) of `values`; 0 for no values.
pub fn quantile(values: &[f32], q: f32) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    v.sort_unstable_by(f32::total_cmp);
    let rank = ((q.clamp(0.0, 1.0) * v.len() as f32).ceil() as usize).clamp(1, v.len());
    v[rank - 1]
}

/// Samples per pixel side behind the coverage masks: a pixel is covered when at least half of
/// its `SUPERSAMPLE²` samples are, and its normal is the mean of its covered samples' normals.
/// With one sample per pixel a sheet thinner than a pixel seen edge on rasterises as a dotted
/// line whose gaps depend on where its triangles fall, so two renders of the same surface could
/// disagree pixels away from any silhouette; area coverage makes the masks a property of the
/// surface rather than of its triangulation.
pub const SUPERSAMPLE: u32 = 3;

/// Area coverage and mean normals of `size` pixels from samples `s` times denser per side
/// (row-major, `size[0] * s` samples wide).
pub fn area_coverage(
    coverage: &[f32],
    normals: &[[f32; 3]],
    size: [u32; 2],
    s: u32,
) -> (Vec<bool>, Vec<[f32; 3]>) {
    let [w, h] = [size[0] as usize, size[1] as usize];
    let (s, big_w) = (s as usize, size[0] as usize * s as usize);
    let mut mask = Vec::with_capacity(w * h);
    let mut mean = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let mut count = 0;
            let mut n = glam::Vec3::ZERO;
            for sy in 0..s {
                for sx in 0..s {
                    let k = (y * s + sy) * big_w + x * s + sx;
                    if coverage[k] > 0.5 {
                        count += 1;
                        n += glam::Vec3::from(normals[k]);
                    }
                }
            }
            mask.push(2 * count >= s * s);
            mean.push(n.normalize_or_zero().to_array());
        }
    }
    (mask, mean)
}

/// Compares candidate and reference coverage masks and normals (row-major, `width × height`).
///
/// ```
/// use subdiv_quality::compare_frames;
/// let (w, h) = (8, 8);
/// // Reference: the left half covered; candidate: one column more.
/// let reference: Vec<bool> = (0..w * h).map(|i| i % w < 4).collect();
/// let candidate: Vec<bool> = (0..w * h).map(|i| i % w < 5).collect();
/// let n = vec![[0.0, 0.0, 1.0]; w * h];
/// let e = compare_frames(&candidate, &n, &reference, &n, w, h);
/// assert_eq!(e.silhouette_px, vec![0.5; 8]); // column 4 lies half a pixel off the silhouette
/// assert!(e.shading_deg.iter().all(|&a| a == 0.0));
/// ```
pub fn compare_frames(
    candidate: &[bool],
    candidate_normals: &[[f32; 3]],
    reference: &[bool],
    reference_normals: &[[f32; 3]],
    width: usize,
    height: usize,
) -> FrameErrors {
    let distance = silhouette_distance(reference, width, height);
    compare_with_distance(
        candidate,
        candidate_normals,
        reference,
        reference_normals,
        &distance,
        &[],
    )
}

/// [`compare_frames`] with the reference's silhouette distance per pixel given (for example
/// [`sample_silhouette_distance`], computed once per reference frame) and its line pixels
/// ([`super::lines::line_pixels`]; empty: none).
pub fn compare_with_distance(
    candidate: &[bool],
    candidate_normals: &[[f32; 3]],
    reference: &[bool],
    reference_normals: &[[f32; 3]],
    distance: &[f32],
    lines: &[bool],
) -> FrameErrors {
    let n = distance.len();
    assert!(
        candidate.len() == n && reference.len() == n,
        "mask sizes must be width × height"
    );
    assert!(
        lines.is_empty() || lines.len() == n,
        "the line mask is empty or width × height"
    );
    let mut out = FrameErrors::default();
    for i in 0..n {
        if candidate[i] != reference[i] {
            out.silhouette_px.push(distance[i]);
        } else if candidate[i] {
            let a = angle_deg(candidate_normals[i], reference_normals[i]);
            out.shading_deg.push(a);
            if !lines.get(i).copied().unwrap_or(false) {
                out.shading_deg_off_lines.push(a);
            }
        }
    }
    out
}

/// Angle between two (unit or not) normals in degrees; 0 when either is zero.
#[inline]
pub(super) fn angle_deg(a: [f32; 3], b: [f32; 3]) -> f32 {
    let (a, b) = (glam::Vec3::from(a), glam::Vec3::from(b));
    let (la, lb) = (a.length(), b.length());
    if la == 0.0 || lb == 0.0 {
        return 0.0;
    }
    (a.dot(b) / (la * lb)).clamp(-1.0, 1.0).acos().to_degrees()
}

/// Per pixel: Euclidean distance (pixels) from its centre to the nearest midpoint of a pixel
/// edge between a covered and an uncovered pixel of `mask`; `f32::INFINITY` for every pixel
/// when the mask has no such edge. Pixels outside the image count as uncovered.
pub fn silhouette_distance(mask: &[bool], width: usize, height: usize) -> Vec<f32> {
    let mut grid = HalfGrid::new(width, height);
    if !grid.mark_boundary(mask) {
        return vec![f32::INFINITY; width * height];
    }
    grid.distances(1)
}

/// A grid of half cells over a `width × height` image of cells (pixels or samples): cell
/// `(x, y)` has its centre at `(2x + 1, 2y + 1)`, the edge between `(x, y)` and `(x + 1, y)`
/// its midpoint at `(2x + 2, 2y + 1)`. Sites hold 0, other nodes infinity, until
/// [`HalfGrid::distances`] turns them into squared distances.
struct HalfGrid {
    width: usize,
    height: usize,
    gw: usize,
    gh: usize,
    grid: Vec<f64>,
}

impl HalfGrid {
    fn new(width: usize, height: usize) -> HalfGrid {
        let (gw, gh) = (2 * width + 1, 2 * height + 1);
        HalfGrid {
            width,
            height,
            gw,
            gh,
            grid: vec![f64::INFINITY; gw * gh],
        }
    }

    /// Marks the midpoint of every edge between a covered and an uncovered cell of `mask`
    /// (cells outside count as uncovered); `false` when there is none.
    fn mark_boundary(&mut self, mask: &[bool]) -> bool {
        let (width, height, gw) = (self.width, self.height, self.gw);
        let covered = |x: isize, y: isize| {
            x >= 0
                && y >= 0
                && (x as usize) < width
                && (y as usize) < height
                && mask[y as usize * width + x as usize]
        };
        let mut any = false;
        for y in 0..height as isize {
            for x in -1..width as isize {
                if covered(x, y) != covered(x + 1, y) {
                    self.grid[(2 * y as usize + 1) * gw + (2 * x + 2) as usize] = 0.0;
                    any = true;
                }
            }
        }
        for y in -1..height as isize {
            for x in 0..width as isize {
                if covered(x, y) != covered(x, y + 1) {
                    self.grid[(2 * y + 2) as usize * gw + 2 * x as usize + 1] = 0.0;
                    any = true;
                }
            }
        }
        any
    }

    /// Marks the grid nodes nearest to points at most a quarter cell apart along the segment
    /// `a`–`b` (in cells, `(0, 0)` the image's corner), inside the image; `false` when none is.
    fn mark_segment(&mut self, a: [f32; 2], b: [f32; 2]) -> bool {
        let (a, b) = (glam::Vec2::from(a) * 2.0, glam::Vec2::from(b) * 2.0);
        let steps = ((b - a).length() * 2.0).ceil().clamp(1.0, 1e6) as usize;
        let mut any = false;
        for k in 0..=steps {
            let p = (a + (b - a) * (k as f32 / steps as f32)).round();
            if p.x >= 0.0 && p.y >= 0.0 && (p.x as usize) < self.gw && (p.y as usize) < self.gh {
                self.grid[p.y as usize * self.gw + p.x as usize] = 0.0;
                any = true;
            }
        }
        any
    }

    /// Distance from the centre of every `s × s` block's middle cell (`s` odd) to the nearest
    /// site, in blocks (pixels when the cells are samples `s` to a pixel side).
    fn distances(mut self, s: usize) -> Vec<f32> {
        edt_2d(&mut self.grid, self.gw, self.gh);
        let (w, h) = (self.width / s, self.height / s);
        let mut out = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let (cx, cy) = (x * s + s / 2, y * s + s / 2);
                // Squared distance in half cells → cells → blocks.
                let d2 = self.grid[(2 * cy + 1) * self.gw + 2 * cx + 1];
                out.push((d2.sqrt() / 2.0 / s as f64) as f32);
            }
        }
        out
    }
}

/// Per pixel of a `size` image: the distance in pixels from its centre to the reference
/// silhouette located among `coverage`'s samples (`s` per pixel side, `s` odd, row-major,
/// `size[0] * s` wide; a sample is covered above 0.5) — the edges between covered and uncovered
/// samples, measured from the sample in the middle of each pixel, whose centre is the pixel's —
/// and on `contours`: segments in pixel coordinates (`(0, 0)` the image's top left corner),
/// marked at the nearest half-sample grid node every quarter sample (so within
/// `1 / (2 √2 s)` px). A pixel next to a silhouette along pixel edges gets 0.5 px as with
/// [`silhouette_distance`]; one whose neighbour holds a sheet thinner than a pixel gets the
/// distance to that sheet's samples, not to the next pixel the area coverage counts as covered;
/// one next to a contour hidden inside the covered area (a fold or a boundary in front of or
/// behind another layer of the surface) gets the distance to that contour, for the gap a
/// candidate opens there is a silhouette error no larger than the contour's displacement.
/// Infinite everywhere when there is no silhouette at all.
pub fn sample_silhouette_distance(
    coverage: &[f32],
    size: [u32; 2],
    s: u32,
    contours: &[[[f32; 2]; 2]],
) -> Vec<f32> {
    assert!(
        s % 2 == 1,
        "the middle sample of a pixel needs an odd supersampling"
    );
    let [w, h, s] = [size[0] as usize, size[1] as usize, s as usize];
    let mask: Vec<bool> = coverage.iter().map(|&c| c > 0.5).collect();
    let mut grid = HalfGrid::new(w * s, h * s);
    let mut any = grid.mark_boundary(&mask);
    for &[a, b] in contours {
        let scale = |p: [f32; 2]| [p[0] * s as f32, p[1] * s as f32];
        any |= grid.mark_segment(scale(a), scale(b));
    }
    if !any {
        return vec![f32::INFINITY; w * h];
    }
    grid.distances(s)
}

/// In-place squared Euclidean distance transform of a grid holding 0 at sites and infinity
/// elsewhere (Felzenszwalb & Huttenlocher 2012): columns, then rows.
fn edt_2d(grid: &mut [f64], w: usize, h: usize) {
    let n = w.max(h);
    let (mut f, mut d) = (vec![0.0f64; n], vec![0.0f64; n]);
    let (mut v, mut z) = (vec![0usize; n], vec![0.0f64; n + 1]);
    for x in 0..w {
        for y in 0..h {
            f[y] = grid[y * w + x];
        }
        edt_1d(&f[..h], &mut d[..h], &mut v, &mut z);
        for y in 0..h {
            grid[y * w + x] = d[y];
        }
    }
    for y in 0..h {
        f[..w].copy_from_slice(&grid[y * w..(y + 1) * w]);
        edt_1d(&f[..w], &mut d[..w], &mut v, &mut z);
        grid[y * w..(y + 1) * w].copy_from_slice(&d[..w]);
    }
}

/// One-dimensional squared distance transform of sampled function `f` (lower envelope of
/// parabolas); infinite samples are no sites.
fn edt_1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    let mut k: usize = 0;
    let Some(q0) = f.iter().position(|x| x.is_finite()) else {
        d.fill(f64::INFINITY);
        return;
    };
    v[0] = q0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in q0 + 1..n {
        if !f[q].is_finite() {
            continue;
        }
        // z[0] is -inf, so the loop stops at k = 0 at the latest.
        let s = loop {
            let p = v[k];
            let s = ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q - p) as f64);
            if s <= z[k] {
                k -= 1;
            } else {
                break s;
            }
        };
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, dq) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        let dx = q as f64 - p as f64;
        *dq = dx * dx + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: distance from each pixel centre to the nearest boundary edge midpoint.
    fn brute(mask: &[bool], w: usize, h: usize) -> Vec<f32> {
        let cov = |x: isize, y: isize| {
            x >= 0
                && y >= 0
                && (x as usize) < w
                && (y as usize) < h
                && mask[y as usize * w + x as usize]
        };
        let mut sites = Vec::new();
        for y in -1..=h as isize {
            for x in -1..=w as isize {
                if cov(x, y) != cov(x + 1, y) {
                    sites.push((x as f32 + 1.0, y as f32 + 0.5));
                }
                if cov(x, y) != cov(x, y + 1) {
                    sites.push((x as f32 + 0.5, y as f32 + 1.0));
                }
            }
        }
        (0..w * h)
            .map(|i| {
                let (px, py) = ((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
                sites
                    .iter()
                    .map(|&(sx, sy)| ((sx - px).powi(2) + (sy - py).powi(2)).sqrt())
                    .fold(f32::INFINITY, f32::min)
            })
            .collect()
    }

    #[test]
    fn distance_transform_matches_brute_force() {
        let (w, h) = (23, 17);
        let mut seed = 12345u32;
        for round in 0..20 {
            // A disc plus random specks.
            let mask: Vec<bool> = (0..w * h)
                .map(|i| {
                    seed ^= seed << 13;
                    seed ^= seed >> 17;
                    seed ^= seed << 5;
                    let (x, y) = ((i % w) as f32 - 11.0, (i / w) as f32 - 8.0);
                    x * x + y * y < (round as f32 * 0.4 + 2.0).powi(2) || seed.is_multiple_of(53)
                })
                .collect();
            let fast = silhouette_distance(&mask, w, h);
            let slow = brute(&mask, w, h);
            for (a, b) in fast.iter().zip(&slow) {
                assert!((a - b).abs() < 1e-4, "round {round}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn sample_distance_finds_sheets_thinner_than_a_pixel() {
        // Pixel-aligned shapes: a straight silhouette gives the pixel mask's distances; around
        // corners the samples' edge midpoints lie closer than the pixels' (at most half a
        // pixel closer).
        let (w, h, s) = (9usize, 7usize, 3usize);
        let upsample = |mask: &[bool]| -> Vec<f32> {
            (0..w * s * h * s)
                .map(|k| f32::from(u8::from(mask[(k / (w * s)) / s * w + (k % (w * s)) / s])))
                .collect()
        };
        let half: Vec<bool> = (0..w * h).map(|i| i % w < 4).collect();
        let fine =
            sample_silhouette_distance(&upsample(&half), [w as u32, h as u32], s as u32, &[]);
        for (a, b) in fine.iter().zip(silhouette_distance(&half, w, h)) {
            assert!((a - b).abs() < 1e-5, "{a} vs {b}");
        }
        let disc: Vec<bool> = (0..w * h)
            .map(|i| ((i % w) as i32 - 4).pow(2) + ((i / w) as i32 - 3).pow(2) < 7)
            .collect();
        let fine =
            sample_silhouette_distance(&upsample(&disc), [w as u32, h as u32], s as u32, &[]);
        for (a, b) in fine.iter().zip(silhouette_distance(&disc, w, h)) {
            assert!(*a <= b + 1e-5 && b <= a + 0.5, "{a} vs {b}");
        }
        // A sheet one sample wide down the middle of pixel 1 of three: no pixel is covered by
        // area, but the silhouette runs through pixel 1 (1/6 px from its centre) and 5/6 px
        // from the centres of pixels 0 and 2.
        let line: Vec<f32> = (0..9 * 3)
            .map(|k| f32::from(u8::from(k % 9 == 4)))
            .collect();
        let d = sample_silhouette_distance(&line, [3, 1], 3, &[]);
        let want = [5.0 / 6.0, 1.0 / 6.0, 5.0 / 6.0];
        for (a, b) in d.iter().zip(want) {
            assert!((a - b).abs() < 1e-5, "{d:?}");
        }
        assert_eq!(
            area_coverage(&line, &[[0.0; 3]; 27], [3, 1], 3).0,
            [false; 3]
        );
        // A contour inside a covered area: a vertical fold at x = 4.5 px of a 9 × 5 image
        // covered everywhere. The pixels' distances are to the fold (the image's edge is the
        // mask's silhouette too).
        let (w, h) = (9usize, 5usize);
        let full = vec![1.0f32; w * 3 * h * 3];
        let fold = [[[4.5f32, -1.0], [4.5, 6.0]]];
        let d = sample_silhouette_distance(&full, [w as u32, h as u32], 3, &fold);
        for (i, v) in d.iter().enumerate() {
            let x = (i % w) as f32 + 0.5;
            let y = (i / w) as f32 + 0.5;
            let edge = x.min(w as f32 - x).min(y).min(h as f32 - y);
            let want = (x - 4.5).abs().min(edge);
            assert!((v - want).abs() <= 0.12, "pixel {i}: {v} vs {want}");
        }
        // Without any silhouette: infinite.
        let none = sample_silhouette_distance(&[0.0; 9], [1, 1], 3, &[]);
        assert!(none[0].is_infinite());
    }

    #[test]
    fn area_coverage_needs_half_a_pixel() {
        // 2 x 1 pixels from 3 x 3 samples each: the left pixel has 5 covered samples (covered),
        // the right one a one-sample-wide line (not covered).
        let (w, s) = (2usize, 3usize);
        let mut cov = vec![0.0f32; w * s * s];
        let mut nrm = vec![[0.0f32; 3]; w * s * s];
        for (k, (c, n)) in cov.iter_mut().zip(nrm.iter_mut()).enumerate() {
            let (x, y) = (k % (w * s), k / (w * s));
            if (x < 3 && (y < 1 || (y == 1 && x < 2))) || x == 4 {
                *c = 1.0;
                *n = [0.0, 0.0, 2.0];
            }
        }
        let (mask, normals) = area_coverage(&cov, &nrm, [2, 1], 3);
        assert_eq!(mask, vec![true, false]);
        assert_eq!(normals[0], [0.0, 0.0, 1.0]);
    }

    #[test]
    fn errors_of_a_shifted_disc_and_tilted_normals() {
        let (w, h) = (40, 30);
        let disc = |cx: f32| -> Vec<bool> {
            (0..w * h)
                .map(|i| {
                    let (x, y) = ((i % w) as f32 + 0.5 - cx, (i / w) as f32 + 0.5 - 15.0);
                    x * x + y * y < 100.0
                })
                .collect()
        };
        let (reference, candidate) = (disc(20.0), disc(23.0));
        let n = vec![[0.0, 0.0, 1.0]; w * h];
        let tilt = 10f32.to_radians();
        let m = vec![[tilt.sin(), 0.0, tilt.cos()]; w * h];
        let e = compare_frames(&candidate, &m, &reference, &n, w, h);
        let max = e.silhouette_px.iter().copied().fold(0.0f32, f32::max);
        assert!(max > 2.0 && max <= 3.0, "{max}");
        assert!(e.shading_deg.iter().all(|&a| (a - 10.0).abs() < 1e-3));
        assert_eq!(quantile(&[3.0, 1.0, 2.0, 4.0], 0.5), 2.0);
        assert_eq!(quantile(&[3.0, 1.0, 2.0, 4.0], 0.99), 4.0);
        assert_eq!(quantile(&[], 0.99), 0.0);
        // Identical frames: no silhouette error.
        let same = compare_frames(&reference, &n, &reference, &n, w, h);
        assert!(same.silhouette_px.is_empty());
        // An empty reference: every candidate pixel is infinitely far from any silhouette.
        let empty = vec![false; w * h];
        assert!(
            silhouette_distance(&empty, w, h)
                .iter()
                .all(|d| d.is_infinite())
        );
    }
}
