//! `cargo xtask figures`, DoI part, §4.3: the idea of the paper's Fig. 10 (details around the
//! dominant objects, fading with distance) on a scene of separate objects of different interest.
//! Measures the triangles per object into `docs/figures/doi_focus.csv` (the text is
//! `figures_doi_text.rs`).

use std::path::Path;

use anyhow::{Context, Result};
use subdiv::{Balance, RefineOptions, refine_adaptive};
use subdiv_doi::{Aggregate, Doi, DoiContext, Focus};
use subdiv_mesh::read_obj;

use crate::figures_doi_text::{FOCUS_OBJECTS, FOCUS_SCENE, STEPS};
use crate::figures_table::Table;

/// Refines the focus scene; one row per object: name, interest (empty for objects that are not
/// dominant), triangles in and out.
pub fn measure(root: &Path) -> Result<Table> {
    let mesh =
        read_obj(root.join(FOCUS_SCENE)).with_context(|| format!("reading {FOCUS_SCENE}"))?;
    let names: Vec<String> = FOCUS_OBJECTS.iter().map(|x| x.to_string()).collect();
    let focus = Focus::from_groups(&mesh, &names, None, Focus::default_radius(&mesh))?;
    let opts = RefineOptions {
        threshold: focus.default_threshold(),
        steps: STEPS,
        aggregate: Aggregate::Max,
        balance: Balance::Vertex,
    };
    let r = refine_adaptive(&mesh, &focus, &DoiContext::default(), &opts)?;
    let out = &r.mesh.mesh;
    let mut t = Table::new(&["object", "interest", "triangles_in", "triangles_out"]);
    for (g, name) in mesh.groups().iter().enumerate() {
        let count =
            |m: &subdiv_mesh::Mesh| m.faces().filter(|&f| m.face_group(f) == g as u32).count();
        let interest = FOCUS_OBJECTS
            .iter()
            .find_map(|o| o.strip_prefix(&format!("{name}=")))
            .unwrap_or("");
        t.push(vec![
            name.clone(),
            interest.to_string(),
            count(&mesh).to_string(),
            count(out).to_string(),
        ]);
    }
    Ok(t)
}
