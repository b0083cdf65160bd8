//! `subdiv-redgreen`: adaptive Loop refinement of a face selection, closed red-green.
//!
//! After T. Isenberg, K. Hartmann and H. König, "Interest Value Driven Adaptive Subdivision"
//! (SimVis 2003), §3 and Fig. 1, with the red-green closure of Amresh & Farin (2002). One step,
//! [`loop_step`], refines the selected triangles 1-to-4, closes their neighbours with green
//! splits, moves the corners of refined triangles by Loop's vertex rule and puts Loop's edge
//! point on every split edge. Which faces to select is the caller's business: a Degree of Interest
//! (`subdiv-doi`, wired by the `subdiv` front door), a distance, a user's brush. This crate knows
//! nothing of DoIs.
//!
//! **Invariants.**
//! - The output of every step is a valid, conforming (crack-free) triangle mesh: every interior
//!   edge has two triangles, the boundary stays the cage's boundary.
//! - Green triangles are never split again: a green triangle that must be refined, or gets a new
//!   vertex on an edge, merges its family back into the parent first.
//! - Balanced steps (the default) keep faces sharing a vertex within one level, and every vertex
//!   where uniform Loop puts it at its level (the highest level of the faces around it).
//! - The rules are `subdiv-rules`' one refinement kernel ([`subdiv_rules::RefineKernel`]): with
//!   every face selected a step is bit-identical to `subdiv_rules::refine_uniform`.
//! - A mesh's UVs (face-varying data, [`subdiv_mesh::Mesh::uv`]) are refined with the same
//!   closure by `subdiv-rules`' face-varying rules ([`subdiv_rules::refine_face_varying_part`]):
//!   with every face selected the channel is `refine_uniform`'s exactly; values are continuous
//!   across every edge off a seam, and seams stay seams.
//! - A mesh's primvars ([`subdiv_mesh::Mesh::primvars`]) are refined in the same passes: vertex
//!   ones by the positions' rules, face-varying ones by the UVs', varying ones linearly, uniform
//!   ones per face (`primvars.rs`); a vertex primvar equal to the positions stays equal to them.
//!
//! ```
//! use subdiv_redgreen::{loop_step, AdaptiveMesh};
//! use subdiv_mesh::{parse_obj, Mesh};
//! let oct = Mesh::from_soup(&parse_obj("v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
//!     f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n")?)?;
//! let mut a = AdaptiveMesh::new(oct)?;
//! for _ in 0..3 {
//!     // Refine the faces above the equator.
//!     let sel: Vec<bool> = a.mesh.faces().map(|f| a.mesh.face_centroid(f).z > 0.0).collect();
//!     a = loop_step(&a, &sel)?.0;
//! }
//! assert!(a.mesh.edges().all(|e| !a.mesh.is_boundary_edge(e))); // still closed
//! assert!(a.mesh.num_faces() < 8 * 64); // fewer than uniform Loop
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;
mod fvar;
mod pass;
mod primvars;
#[cfg(test)]
mod primvars_tests;
pub mod red_green;
mod step;

pub use error::RedGreenError;
pub use red_green::{GreenFamily, GreenState};
pub use step::{AdaptiveMesh, Balance, MAX_TRIANGLES, StepStats, loop_step, loop_step_with};
