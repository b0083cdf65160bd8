//! Line pixels of a render: where the true normal turns by more than a tolerance from one pixel
//! to the next (crease lines, folds, strips narrower than a pixel). The shading error off them is
//! what `--shading-error` bounds ([`super::ConfigQuality::shading_deg_p99_off_lines`]).

use super::metrics::angle_deg;

/// Per pixel: whether it is a *line pixel* of the render (`coverage`, `normals`): a covered
/// pixel whose normal turns by more than `turn_deg` degrees to that of a covered neighbour (of
/// eight). There the true shading changes by more than the tolerance within a pixel (a crease
/// line, a fold, a strip narrower than a pixel), so a pixel shows a blend that depends on where
/// the line falls in it, in the reference as in any tessellation.
pub fn line_pixels(
    coverage: &[bool],
    normals: &[[f32; 3]],
    width: usize,
    height: usize,
    turn_deg: f32,
) -> Vec<bool> {
    let n = width * height;
    assert!(
        coverage.len() == n && normals.len() == n,
        "mask sizes must be width × height"
    );
    let mut line = vec![false; n];
    for y in 0..height {
        for x in 0..width {
            let i = y * width + x;
            if !coverage[i] {
                continue;
            }
            'neighbours: for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if (dx, dy) == (0, 0)
                        || nx < 0
                        || ny < 0
                        || nx >= width as i64
                        || ny >= height as i64
                    {
                        continue;
                    }
                    let j = ny as usize * width + nx as usize;
                    if coverage[j] && angle_deg(normals[i], normals[j]) > turn_deg {
                        line[i] = true;
                        break 'neighbours;
                    }
                }
            }
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::{compare_with_distance, silhouette_distance};

    /// A crease down the middle of a covered square: the two columns beside it are line pixels
    /// above the crease's turn and none below; uncovered neighbours never make one; the errors
    /// off the lines leave out exactly those pixels.
    #[test]
    fn line_pixels_are_where_the_normal_turns_within_a_pixel() {
        let (w, h) = (8, 6);
        let coverage: Vec<bool> = (0..w * h).map(|i| i % w < 6).collect();
        let turn = 30f32.to_radians();
        let normals: Vec<[f32; 3]> = (0..w * h)
            .map(|i| {
                if i % w < 3 {
                    [0.0, 0.0, 1.0]
                } else {
                    [turn.sin(), 0.0, turn.cos()]
                }
            })
            .collect();
        let lines = line_pixels(&coverage, &normals, w, h, 10.0);
        for (i, &l) in lines.iter().enumerate() {
            assert_eq!(l, i % w == 2 || i % w == 3, "pixel {i}");
        }
        assert!(!line_pixels(&coverage, &normals, w, h, 31.0).contains(&true));
        let distance = silhouette_distance(&coverage, w, h);
        let flat = vec![[0.0, 0.0, 1.0]; w * h];
        let e = compare_with_distance(&coverage, &flat, &coverage, &normals, &distance, &lines);
        assert_eq!(e.shading_deg.len(), 36);
        assert_eq!(e.shading_deg_off_lines.len(), 36 - 12);
        let off_max = e
            .shading_deg_off_lines
            .iter()
            .copied()
            .fold(0.0f32, f32::max);
        assert!((off_max - 30.0).abs() < 1e-3, "{off_max}");
        let none = compare_with_distance(&coverage, &flat, &coverage, &normals, &distance, &[]);
        assert_eq!(none.shading_deg_off_lines, none.shading_deg);
    }
}
