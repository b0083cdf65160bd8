//! The DoIs by name: [`DoiKind`], the one home of the names the command line, the set-up and the
//! DoIs themselves ([`crate::Doi::name`]) use.

/// The Degree-of-Interest functions a program can choose by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DoiKind {
    /// Angle between the view direction and the surface ([`crate::ViewAngle`]).
    ViewAngle,
    /// Closeness to the silhouette ([`crate::Silhouette`]).
    Silhouette,
    /// Dihedral angle at the edges ([`crate::Dihedral`]).
    Dihedral,
    /// Haptic: the Clough-Tocher G1 error and one-side criterion ([`crate::Haptic`], tolerance
    /// 5 % of the mean edge length), or the neighbourhood of a haptic interaction point when
    /// one is given ([`crate::HapticPoint`]).
    Haptic,
    /// Distance to focus objects or a skeleton ([`crate::Focus`]).
    Focus,
    /// How much the surface bends at each vertex ([`crate::Curvature`]; vertex values,
    /// aggregated to faces).
    Curvature,
}

impl DoiKind {
    /// Every kind, in the order of the paper's figures, then the vertex DoI.
    pub const ALL: [DoiKind; 6] = [
        DoiKind::ViewAngle,
        DoiKind::Silhouette,
        DoiKind::Dihedral,
        DoiKind::Haptic,
        DoiKind::Focus,
        DoiKind::Curvature,
    ];

    /// The kind's name: `view-angle`, `silhouette`, `dihedral`, `haptic`, `focus` or
    /// `curvature`.
    pub const fn name(self) -> &'static str {
        match self {
            DoiKind::ViewAngle => "view-angle",
            DoiKind::Silhouette => "silhouette",
            DoiKind::Dihedral => "dihedral",
            DoiKind::Haptic => "haptic",
            DoiKind::Focus => "focus",
            DoiKind::Curvature => "curvature",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_its_command_line_name() {
        assert_eq!(
            DoiKind::ALL.map(DoiKind::name),
            [
                "view-angle",
                "silhouette",
                "dihedral",
                "haptic",
                "focus",
                "curvature"
            ]
        );
    }
}
