//! Built-in scenes: cages that ship inside the library, for the figures and benchmarks.

use glam::Vec3;
use subdiv_mesh::{Mesh, MeshError, parse_obj, point_bounds};

/// Cage file of the built-in `helmet40` scene's model (`catmark_helmet`, 58 faces); `data/` links
/// to `fixtures/reference/shapes/` so that `cargo package` ships the file inside the crate.
const HELMET_OBJ: &str = include_str!("../data/catmark_helmet.obj");

/// Why a built-in scene could not be built (only if the embedded cage were broken).
#[derive(Debug, thiserror::Error)]
pub enum BuiltinError {
    /// The embedded cage does not parse.
    #[error("embedded catmark_helmet")]
    EmbeddedCage(#[source] MeshError),
    /// The instanced cage is not a valid mesh.
    #[error("helmet40 scene")]
    Scene(#[source] MeshError),
}

/// A scene built into the library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BuiltinScene {
    /// The paper's Fig. 12: 40 instances of `catmark_helmet` on an 8 x 5 grid ([`helmet40`]).
    Helmet40,
}

impl BuiltinScene {
    /// Every built-in scene.
    pub const ALL: [BuiltinScene; 1] = [BuiltinScene::Helmet40];

    /// The scene's name (`helmet40`).
    pub fn name(self) -> &'static str {
        match self {
            BuiltinScene::Helmet40 => "helmet40",
        }
    }

    /// Builds the scene's cage.
    pub fn cage(self) -> Result<Mesh, BuiltinError> {
        match self {
            BuiltinScene::Helmet40 => helmet40(),
        }
    }
}

/// The model of [`helmet40`]: OpenSubdiv's `catmark_helmet` (58 quads, semi-sharp creases).
pub fn helmet() -> Result<Mesh, BuiltinError> {
    let soup = parse_obj(HELMET_OBJ).map_err(BuiltinError::EmbeddedCage)?;
    Mesh::from_soup(&soup).map_err(BuiltinError::EmbeddedCage)
}

/// The test scene of the paper's Fig. 12: 40 instances of `catmark_helmet` (58 faces each) on an
/// 8 x 5 grid in the XZ plane, 1.25 model widths apart ([`instance_grid`]).
pub fn helmet40() -> Result<Mesh, BuiltinError> {
    instance_grid(&helmet()?, 40).map_err(BuiltinError::Scene)
}

/// Copies of the grid of [`instance_grid`] per row.
pub const GRID_COLUMNS: usize = 8;

/// `n` copies of `mesh` laid out as the paper's Fig. 12 lays out its helmets: rows of
/// [`GRID_COLUMNS`] in the XZ plane, `1.25` times the model's larger horizontal extent apart,
/// centred on the model's own position (`n = 40`: [`helmet40`]'s 8 x 5 grid).
pub fn instance_grid(mesh: &Mesh, n: usize) -> Result<Mesh, MeshError> {
    let (lo, hi) = point_bounds(mesh.positions().iter().copied());
    let ext = hi - lo;
    let step = 1.25 * ext.x.max(ext.z);
    let cols = n.min(GRID_COLUMNS);
    let rows = n.div_ceil(GRID_COLUMNS.max(1));
    let (cx, cz) = ((cols as f32 - 1.0) * 0.5, (rows as f32 - 1.0) * 0.5);
    let offsets: Vec<Vec3> = (0..n)
        .map(|k| {
            let (row, col) = (k / GRID_COLUMNS, k % GRID_COLUMNS);
            Vec3::new((col as f32 - cx) * step, 0.0, (row as f32 - cz) * step)
        })
        .collect();
    mesh.instanced(&offsets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn instance_grids_are_centred_rows_of_eight() {
        let helmet = Mesh::from_soup(&parse_obj(HELMET_OBJ).unwrap()).unwrap();
        let (lo, hi) = helmet.bounds();
        let centre = (lo + hi) * 0.5;
        for n in [1usize, 3, 8, 9, 40] {
            let m = instance_grid(&helmet, n).unwrap();
            assert_eq!(m.num_faces(), 58 * n);
            let (a, b) = m.bounds();
            // Centred on the model: the grid's middle is the model's middle.
            assert!(((a + b) * 0.5 - centre).length() < 1e-4 * (b - a).length(), "{n}");
            let ext = hi - lo;
            let step = 1.25 * ext.x.max(ext.z);
            let cols = n.min(8) as f32;
            assert!(((b.x - a.x) - ((cols - 1.0) * step + ext.x)).abs() < 1e-3, "{n}");
        }
        assert!(instance_grid(&helmet, 0).is_err());
    }

    #[test]
    fn helmet40_is_forty_helmets_on_a_grid() {
        let m = BuiltinScene::Helmet40.cage().unwrap();
        assert_eq!(m.num_faces(), 40 * 58);
        let (lo, hi) = m.bounds();
        // Eight columns along x, five rows along z.
        assert!(hi.x - lo.x > hi.z - lo.z);
        assert_eq!(BuiltinScene::ALL.map(BuiltinScene::name), ["helmet40"]);
    }
}
