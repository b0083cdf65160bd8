//! [`StencilTessellator`]: the uniform tessellation of a moving cage, frame after frame.

use subdiv_mesh::Mesh;
use subdiv_rules::{Depth, LimitMesh, Scheme};
use subdiv_slate::UniformTessellator;

use crate::{StencilError, StencilTable};

/// Deepest depth a table is made for. Measured one thread (docs/performance.md, "Moving
/// cages"), a table's frame is faster than the slates' at depths 2 and 3 on every cage, and at
/// depth 4 as fast (the pawn, the bunny) or faster (the helmet, 6x); deeper, a face holds
/// hundreds of points, the slates' per-face set-up is small beside them, and the table (and
/// the time to make it) grows four times a level.
pub const MAX_STENCIL_DEPTH: Depth = 4;

/// The uniform limit tessellation of a cage that moves between calls, as
/// [`UniformTessellator`] but with each frame's points and normals from a [`StencilTable`]
/// where one is made (see the crate notes): [`StencilTessellator::update`] with the cage of a
/// frame rewrites points and normals in the same surface, whose faces stay
/// ([`LimitMesh::topology_written`] is `false`), and lays the cage out again when its topology
/// changed.
///
/// The frame a layout is made with (the first, and the first after a change of topology) is
/// the slates' tessellation, bit for bit what `subdiv_slate::tessellate` gives (a still
/// picture of a moving cage equals the static cage's); the frames through the table agree with
/// it to rounding.
#[derive(Debug)]
pub struct StencilTessellator {
    slates: UniformTessellator,
    table: Option<StencilTable>,
}

impl StencilTessellator {
    /// Lays out the `scheme` surface of `mesh` at `depth`, makes its stencil table where one
    /// is made, and tessellates the first frame (errors as the slates and the evaluator give
    /// them).
    pub fn new(
        mesh: &Mesh,
        scheme: Scheme,
        depth: Depth,
    ) -> Result<StencilTessellator, StencilError> {
        let mut t = StencilTessellator {
            slates: UniformTessellator::new(mesh, scheme, depth)?,
            table: None,
        };
        t.make_table(mesh)?;
        Ok(t)
    }

    /// The surface of `mesh`, a later frame of the cage: points and normals rewritten while
    /// the topology stays; a cage of another topology is laid out again (and gets its own
    /// table). On an error the last surface is kept.
    pub fn update(&mut self, mesh: &Mesh) -> Result<&LimitMesh, StencilError> {
        match &self.table {
            Some(table) if self.slates.same_topology(mesh) => {
                subdiv_rules::check_coordinates(mesh).map_err(subdiv_slate::SlateError::from)?;
                let out = self.slates.surface_mut();
                let (pos, nrm) = out.points_and_normals_mut();
                table.apply(mesh, pos, nrm)?;
                out.keep_faces();
            }
            _ => {
                let relaid = !self.slates.same_topology(mesh);
                self.slates.update(mesh)?;
                if relaid {
                    self.make_table(mesh)?;
                }
            }
        }
        Ok(self.slates.surface())
    }

    /// The last frame's surface.
    pub fn surface(&self) -> &LimitMesh {
        self.slates.surface()
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.slates.scheme()
    }

    /// The depth.
    pub fn depth(&self) -> Depth {
        self.slates.depth()
    }

    /// How many layouts were made: one, plus one per change of topology.
    pub fn layouts_built(&self) -> u64 {
        self.slates.layouts_built()
    }

    /// The table the frames are computed with (`None`: the slates run every frame).
    pub fn stencils(&self) -> Option<&StencilTable> {
        self.table.as_ref()
    }

    /// The table of the current layout, where one is made (the frame the layout was made with
    /// stays the slates').
    fn make_table(&mut self, mesh: &Mesh) -> Result<(), StencilError> {
        self.table = None;
        let depth = self.slates.depth();
        // One-sided normals (infinitely sharp creases and corners) are the slates' alone.
        let sided = !self.slates.surface().corner_normals().is_empty();
        if depth > MAX_STENCIL_DEPTH || !mesh.primvars().is_empty() || sided {
            return Ok(());
        }
        let Some(params) = self.slates.point_params() else {
            return Ok(());
        };
        self.table = match StencilTable::new(mesh, self.slates.scheme(), &params, u32::from(depth))
        {
            Ok(table) => Some(table),
            // A limit the table cannot hold, or a table too large: the slates compute every
            // frame.
            Err(StencilError::Support { .. } | StencilError::TooLarge { .. }) => None,
            Err(e) => return Err(e),
        };
        Ok(())
    }
}
