//! Reading input cages.

use std::path::Path;

use subdiv_mesh::{read_obj_with, Mesh, ReadOptions};

/// Reads and validates a cage; errors read `FILE:LINE: what`.
pub fn load_mesh(path: &Path, split_nonmanifold: bool) -> anyhow::Result<Mesh> {
    Ok(read_obj_with(path, ReadOptions { split_nonmanifold_vertices: split_nonmanifold })?)
}
