//! Reading input cages.

use std::path::Path;

use subdiv::mesh::{Mesh, ReadOptions, read_obj_with};

/// Reads and validates a cage; errors read `FILE:LINE: what`.
pub fn load_mesh(path: &Path, split_nonmanifold: bool) -> anyhow::Result<Mesh> {
    Ok(read_obj_with(
        path,
        ReadOptions {
            split_nonmanifold_vertices: split_nonmanifold,
        },
    )?)
}
