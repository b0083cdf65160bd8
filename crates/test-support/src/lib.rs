//! Helpers shared by the tests of every workspace crate: the random generator ([`Rng`]), the
//! watertightness check over plain triangle buffers ([`open_edges`] and its parts), small cages
//! as polygon soups or OBJ text ([`cube`], [`prism`], [`grid`]), the fixture paths
//! ([`fixture`]), recorded output hashes ([`Fnv`], [`check_recorded`]) and how far two
//! tessellations of one surface lie apart ([`max_deviation`]).
//!
//! The crate depends on no workspace crate, so a crate's own unit tests can use it without
//! linking a second copy of that crate: its helpers take and return plain buffers
//! (`[f32; 3]` positions, `u32` indices), which the tests turn into meshes with their own
//! `parse_obj` or `PolygonSoup::from_faces`.

mod cages;
mod deviation;
mod fixtures;
mod hashes;
mod rng;
mod watertight;

pub use cages::{
    Soup, colours_from, colours_from_positions, cube, grid, grouped_cube_obj, height_grid, prism,
};
pub use deviation::max_deviation;
pub use fixtures::{fixture, fixture_files, fixtures, root, shape};
pub use hashes::{Fnv, check_recorded, trig_fingerprint};
pub use rng::Rng;
pub use watertight::{
    indexed_open_edges, open_edges, open_edges_by, weld, weld_values, welded_open_edges,
};
