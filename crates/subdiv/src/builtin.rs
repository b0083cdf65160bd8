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

/// The test scene of the paper's Fig. 12: 40 instances of `catmark_helmet` (58 faces each) on an
/// 8 x 5 grid in the XZ plane, 1.25 model widths apart.
pub fn helmet40() -> Result<Mesh, BuiltinError> {
    let soup = parse_obj(HELMET_OBJ).map_err(BuiltinError::EmbeddedCage)?;
    let (lo, hi) = point_bounds(soup.positions.iter().copied());
    let ext = hi - lo;
    let step = 1.25 * ext.x.max(ext.z);
    let offsets: Vec<Vec3> = (0..5)
        .flat_map(|row| {
            (0..8).map(move |col| {
                Vec3::new((col as f32 - 3.5) * step, 0.0, (row as f32 - 2.0) * step)
            })
        })
        .collect();
    Mesh::from_soup(&soup.instanced(&offsets)).map_err(BuiltinError::Scene)
}

#[cfg(test)]
mod tests {
    use super::*;

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
