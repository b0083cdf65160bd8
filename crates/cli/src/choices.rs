//! The closed choices of the command line as `clap::ValueEnum`s, each naming the library value
//! it stands for. The value names are the command line's (`catmull-clark`, `view-angle`, ...).

use clap::ValueEnum;
use subdiv::BuiltinScene;
use subdiv::doi::Aggregate;
use subdiv::rules::Scheme;
use subdiv::vk::Shading;

/// The value name of a choice as written on the command line.
pub fn value_name<E: ValueEnum>(e: &E) -> String {
    e.to_possible_value()
        .map(|v| v.get_name().to_owned())
        .unwrap_or_default()
}

/// `--scheme`: the subdivision scheme.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SchemeName {
    CatmullClark,
    Loop,
    Bilinear,
}

impl From<Scheme> for SchemeName {
    fn from(s: Scheme) -> SchemeName {
        match s {
            Scheme::CatmullClark => SchemeName::CatmullClark,
            Scheme::Loop => SchemeName::Loop,
            Scheme::Bilinear => SchemeName::Bilinear,
        }
    }
}

impl From<SchemeName> for Scheme {
    fn from(s: SchemeName) -> Scheme {
        match s {
            SchemeName::CatmullClark => Scheme::CatmullClark,
            SchemeName::Loop => Scheme::Loop,
            SchemeName::Bilinear => Scheme::Bilinear,
        }
    }
}

/// `--control`: how an adaptive node meets a target frame rate.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ControlName {
    Budget,
    Paper,
}

impl From<ControlName> for subdiv::Control {
    fn from(c: ControlName) -> subdiv::Control {
        match c {
            ControlName::Budget => subdiv::Control::Budget,
            ControlName::Paper => subdiv::Control::Paper,
        }
    }
}

/// `--scene`: a built-in scene.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneName {
    Helmet40,
}

impl From<SceneName> for BuiltinScene {
    fn from(s: SceneName) -> BuiltinScene {
        match s {
            SceneName::Helmet40 => BuiltinScene::Helmet40,
        }
    }
}

/// `--doi`: the Degree-of-Interest function.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum DoiName {
    ViewAngle,
    Silhouette,
    Dihedral,
    Haptic,
    Focus,
    Curvature,
}

impl From<DoiName> for subdiv::doi::DoiKind {
    fn from(d: DoiName) -> subdiv::doi::DoiKind {
        use subdiv::doi::DoiKind;
        match d {
            DoiName::ViewAngle => DoiKind::ViewAngle,
            DoiName::Silhouette => DoiKind::Silhouette,
            DoiName::Dihedral => DoiKind::Dihedral,
            DoiName::Haptic => DoiKind::Haptic,
            DoiName::Focus => DoiKind::Focus,
            DoiName::Curvature => DoiKind::Curvature,
        }
    }
}

/// `--aggregate`: how edge or vertex DoI values become face values.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum AggregateName {
    Max,
    Avg,
    Min,
}

impl From<AggregateName> for Aggregate {
    fn from(a: AggregateName) -> Aggregate {
        match a {
            AggregateName::Max => Aggregate::Max,
            AggregateName::Avg => Aggregate::Avg,
            AggregateName::Min => Aggregate::Min,
        }
    }
}

/// `--shading`: how the surface is shaded.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadingName {
    Smooth,
    Flat,
    Wire,
    Depth,
    Doi,
}

/// `--shading`: one of the renderer's shadings, or `primvar:NAME` (a primvar of the cage drawn
/// on the surface).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShadingChoice {
    /// A shading of the renderer.
    Mode(ShadingName),
    /// `primvar:NAME`.
    Primvar(String),
}

/// Parses `--shading`: a [`ShadingName`] or `primvar:NAME`.
pub fn parse_shading(s: &str) -> Result<ShadingChoice, String> {
    if let Some(name) = s.strip_prefix("primvar:") {
        if name.is_empty() {
            return Err("primvar: needs a name (primvar:displayColor, primvar:st, ...)".into());
        }
        return Ok(ShadingChoice::Primvar(name.to_string()));
    }
    ShadingName::from_str(s, false)
        .map(ShadingChoice::Mode)
        .map_err(|_| {
            let names: Vec<String> = ShadingName::value_variants()
                .iter()
                .map(value_name)
                .collect();
            format!(
                "'{s}' is not a shading: give {} or primvar:NAME",
                names.join(", ")
            )
        })
}

impl From<ShadingName> for Shading {
    fn from(s: ShadingName) -> Shading {
        match s {
            ShadingName::Smooth => Shading::Smooth,
            ShadingName::Flat => Shading::Flat,
            ShadingName::Wire => Shading::Wire,
            ShadingName::Depth => Shading::Depth,
            ShadingName::Doi => Shading::Doi,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The value names are the command line's, and each choice names the library value of the
    /// same name.
    #[test]
    fn value_names_match_the_library_names() {
        for s in SchemeName::value_variants() {
            assert_eq!(value_name(s).parse::<Scheme>().unwrap(), Scheme::from(*s));
        }
        for d in DoiName::value_variants() {
            assert_eq!(value_name(d), subdiv::doi::DoiKind::from(*d).name());
        }
        for a in AggregateName::value_variants() {
            assert_eq!(
                value_name(a).parse::<Aggregate>().unwrap(),
                Aggregate::from(*a)
            );
        }
        for s in ShadingName::value_variants() {
            assert_eq!(value_name(s), Shading::from(*s).name());
        }
        for s in SceneName::value_variants() {
            assert_eq!(value_name(s), BuiltinScene::from(*s).name());
        }
        assert_eq!(value_name(&SchemeName::CatmullClark), "catmull-clark");
        assert_eq!(value_name(&DoiName::ViewAngle), "view-angle");
    }

    #[test]
    fn shading_is_a_mode_or_a_primvar() {
        assert_eq!(
            parse_shading("depth"),
            Ok(ShadingChoice::Mode(ShadingName::Depth))
        );
        assert_eq!(
            parse_shading("primvar:displayColor"),
            Ok(ShadingChoice::Primvar("displayColor".into()))
        );
        assert!(parse_shading("primvar:").is_err());
        let e = parse_shading("shiny").unwrap_err();
        assert!(
            e.contains("smooth, flat, wire, depth, doi or primvar:NAME"),
            "{e}"
        );
    }
}
