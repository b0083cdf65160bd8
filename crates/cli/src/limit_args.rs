//! `--max-triangles`: the output limit of every command that tessellates or refines, declared
//! once and flattened where used.

use subdiv::mesh::Mesh;
use subdiv::rules::budget::Limit;
use subdiv::rules::{Budget, MAX_DEPTH, Request};
use subdiv::stitch::MAX_ADAPTIVE_DEPTH;

/// The output limit.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct LimitArgs {
    /// Refuse, before tessellating, output of more than N triangles (a quad counts as two; the
    /// adaptive and DoI paths by their bound: every face at --max-depth, or refined at every
    /// step). Output beyond this machine's memory is refused in any case.
    #[arg(long, value_name = "N")]
    pub max_triangles: Option<u64>,
}

impl LimitArgs {
    /// Refuses `request` on `mesh` beyond `--max-triangles` or this machine's memory, with the
    /// size it asks for; `label` names the input.
    pub fn check(&self, mesh: &Mesh, request: Request, label: &str) -> anyhow::Result<()> {
        // A depth beyond the caps is left to the library, whose error names the cap.
        let beyond_caps = match request {
            Request::Uniform { depth, .. } => depth > MAX_DEPTH,
            Request::Adaptive { max_depth, .. } => max_depth > MAX_ADAPTIVE_DEPTH,
            Request::Refine { .. } => false,
        };
        if beyond_caps {
            return Ok(());
        }
        let budget = Budget::machine().with_max_triangles(self.max_triangles);
        match budget.check(mesh, request) {
            Ok(_) => Ok(()),
            Err(e) if matches!(e.limit, Limit::Triangles { .. }) => {
                anyhow::bail!("{label}: {e} (--max-triangles)")
            }
            Err(e) => anyhow::bail!("{label}: {e}"),
        }
    }
}
