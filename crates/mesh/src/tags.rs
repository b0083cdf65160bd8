//! OpenSubdiv's `t` tag lines in OBJ files: `t name ni/nf/ns ints.. floats.. strings..`.
//!
//! Applied: `crease`, `corner`, `hole`, `interpolateboundary`, `creasemethod` and
//! `smoothtriangles` (spelled as OpenSubdiv's regression shapes spell it,
//! `regression/common/far_utils.h`: `t smoothtriangles 0/0/1 smooth|catmark`; the integer form
//! `1/0/0 1|0` is read too). Every other tag line is read (its counts must match its arguments)
//! but not applied, and leaves a [`TagWarning`] in [`PolygonSoup::warnings`]: OpenSubdiv's
//! hierarchical edits (`vertexedit`, `edgeedit`, `faceedit`), face-varying options, and unknown
//! names.

use std::fmt;

use crate::error::MeshError;
use crate::options::{BoundaryInterpolation, CreaseMethod, TriangleSubdivision};
use crate::soup::{CornerTag, CreaseTag, HoleTag, PolygonSoup};

/// Why a tag line was not applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IgnoredTagKind {
    /// A name the reader does not know.
    Unknown,
    /// One of OpenSubdiv's hierarchical edits (`vertexedit`, `edgeedit`, `faceedit`), which
    /// subdiv does not implement.
    HierarchicalEdit,
    /// A face-varying option other than `facevaryinginterpolateboundary` (e.g. OpenSubdiv 2's
    /// `facevaryingpropagatecorners`), which subdiv does not apply.
    FaceVarying,
}

/// A tag line that was read but not applied.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TagWarning {
    /// 1-based line of the tag in its file.
    pub line: u32,
    /// The tag's name (the word after `t`).
    pub name: String,
    /// Why it was not applied.
    pub kind: IgnoredTagKind,
}

impl TagWarning {
    /// `line 12: t vertexedit` (the form `subdiv info` lists).
    pub fn short(&self) -> String {
        format!("line {}: t {}", self.line, self.name)
    }
}

impl fmt::Display for TagWarning {
    /// `LINE: tag 't NAME' ignored (why)`, to be prefixed with the file name.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let why = match self.kind {
            IgnoredTagKind::Unknown => "unknown tag",
            IgnoredTagKind::HierarchicalEdit => "hierarchical edits are not supported",
            IgnoredTagKind::FaceVarying => "this face-varying option is not applied",
        };
        write!(f, "{}: tag 't {}' ignored ({why})", self.line, self.name)
    }
}

/// Applies one tag line (the tokens after `t`) to `soup`, or records why it was not applied.
pub(crate) fn parse_tag(
    soup: &mut PolygonSoup,
    toks: Vec<&str>,
    line: u32,
) -> Result<(), MeshError> {
    let args = TagArgs::parse(&toks, line)?;
    match args.name {
        "crease" => crease_tags(soup, &args, line)?,
        "corner" => corner_tags(soup, &args, line)?,
        "hole" => soup.holes.extend(args.ints.iter().map(|&f| HoleTag {
            f,
            line: Some(line),
        })),
        "interpolateboundary" => soup.options.boundary = boundary_option(&args, line)?,
        "creasemethod" => soup.options.crease = crease_option(&args, line)?,
        "smoothtriangles" => soup.options.triangles = triangles_option(&args, line)?,
        "facevaryinginterpolateboundary" => soup.options.fvar = fvar_option(&args, line)?,
        name => soup.warnings.push(TagWarning {
            line,
            name: name.to_string(),
            kind: ignored_kind(name),
        }),
    }
    Ok(())
}

fn perr(line: u32, msg: String) -> MeshError {
    MeshError::Parse { line, msg }
}

/// A tag line `t name ni/nf/ns args..` with its arguments split by type.
struct TagArgs<'a> {
    name: &'a str,
    ints: Vec<i64>,
    floats: Vec<f32>,
    strings: &'a [&'a str],
}

impl<'a> TagArgs<'a> {
    /// Splits the tokens after `t`, checking the counts against the arguments and parsing the
    /// integers and numbers (for every tag, known or not).
    fn parse(toks: &'a [&'a str], line: u32) -> Result<TagArgs<'a>, MeshError> {
        let name = *toks
            .first()
            .ok_or_else(|| perr(line, "tag without a name".into()))?;
        let counts = toks
            .get(1)
            .ok_or_else(|| perr(line, format!("tag '{name}' without counts n/n/n")))?;
        let c: Vec<usize> = counts
            .split('/')
            .map(|x| x.parse::<usize>())
            .collect::<Result<_, _>>()
            .map_err(|_| perr(line, format!("tag '{name}': invalid counts '{counts}'")))?;
        if c.len() != 3 {
            return Err(perr(
                line,
                format!("tag '{name}': counts must be ints/floats/strings, got '{counts}'"),
            ));
        }
        let args = &toks[2..];
        // Checked: counts near `usize::MAX` must not wrap around to the number of arguments.
        let announced = c[0].checked_add(c[1]).and_then(|n| n.checked_add(c[2]));
        if announced != Some(args.len()) {
            return Err(perr(
                line,
                format!(
                    "tag '{name}': counts {counts} announce {} arguments, found {}",
                    announced.map_or_else(|| "too many".to_string(), |n| n.to_string()),
                    args.len()
                ),
            ));
        }
        let ints: Vec<i64> = args[..c[0]]
            .iter()
            .map(|t| {
                t.parse::<i64>()
                    .map_err(|_| perr(line, format!("tag '{name}': invalid integer '{t}'")))
            })
            .collect::<Result<_, _>>()?;
        let floats: Vec<f32> = args[c[0]..c[0] + c[1]]
            .iter()
            .map(|t| {
                t.parse::<f32>()
                    .map_err(|_| perr(line, format!("tag '{name}': invalid number '{t}'")))
            })
            .collect::<Result<_, _>>()?;
        Ok(TagArgs {
            name,
            ints,
            floats,
            strings: &args[c[0] + c[1]..],
        })
    }
}

/// `t crease`: a chain of vertices, one sharpness for all its edges or one per edge.
fn crease_tags(soup: &mut PolygonSoup, args: &TagArgs<'_>, line: u32) -> Result<(), MeshError> {
    let (ints, floats) = (&args.ints, &args.floats);
    if ints.len() < 2 {
        return Err(perr(line, "crease tag needs at least two vertices".into()));
    }
    let edges = ints.len() - 1;
    if floats.len() != 1 && floats.len() != edges {
        return Err(perr(
            line,
            format!(
                "crease tag over {edges} edges needs 1 or {edges} sharpness values, found {}",
                floats.len()
            ),
        ));
    }
    for k in 0..edges {
        let s = if floats.len() == 1 {
            floats[0]
        } else {
            floats[k]
        };
        soup.creases.push(CreaseTag {
            a: ints[k],
            b: ints[k + 1],
            sharpness: s,
            line: Some(line),
        });
    }
    Ok(())
}

/// `t corner`: vertices, one sharpness for all or one per vertex.
fn corner_tags(soup: &mut PolygonSoup, args: &TagArgs<'_>, line: u32) -> Result<(), MeshError> {
    let (ints, floats) = (&args.ints, &args.floats);
    if floats.len() != 1 && floats.len() != ints.len() {
        return Err(perr(
            line,
            format!(
                "corner tag over {} vertices needs 1 or {} sharpness values, found {}",
                ints.len(),
                ints.len(),
                floats.len()
            ),
        ));
    }
    for (k, &v) in ints.iter().enumerate() {
        let s = if floats.len() == 1 {
            floats[0]
        } else {
            floats[k]
        };
        soup.corners.push(CornerTag {
            v,
            sharpness: s,
            line: Some(line),
        });
    }
    Ok(())
}

/// `t interpolateboundary k`: 0 none, 1 edge-and-corner, 2 edge-only.
fn boundary_option(args: &TagArgs<'_>, line: u32) -> Result<BoundaryInterpolation, MeshError> {
    match args.ints.first() {
        Some(0) => Ok(BoundaryInterpolation::None),
        Some(1) => Ok(BoundaryInterpolation::EdgeAndCorner),
        Some(2) => Ok(BoundaryInterpolation::EdgeOnly),
        other => Err(perr(
            line,
            format!("interpolateboundary: expected 0, 1 or 2, got {other:?}"),
        )),
    }
}

/// `t creasemethod chaikin|uniform` (`normal` is read as uniform).
fn crease_option(args: &TagArgs<'_>, line: u32) -> Result<CreaseMethod, MeshError> {
    match args.strings.first().copied() {
        Some("chaikin") => Ok(CreaseMethod::Chaikin),
        Some("uniform") | Some("normal") => Ok(CreaseMethod::Uniform),
        other => Err(perr(
            line,
            format!("creasemethod: expected chaikin or uniform, got {other:?}"),
        )),
    }
}

/// `t smoothtriangles 0/0/1 smooth|catmark` (OpenSubdiv's spelling), or `1/0/0 1|0`.
fn triangles_option(args: &TagArgs<'_>, line: u32) -> Result<TriangleSubdivision, MeshError> {
    match (args.strings.first().copied(), args.ints.first()) {
        (Some("smooth"), _) | (None, Some(1)) => Ok(TriangleSubdivision::Smooth),
        (Some("catmark"), _) | (None, Some(0)) => Ok(TriangleSubdivision::Catmark),
        (s, i) => Err(perr(
            line,
            format!("smoothtriangles: expected smooth or catmark (or 1 or 0), got {s:?} {i:?}"),
        )),
    }
}

/// `t facevaryinginterpolateboundary 1/0/0 k`: OpenSubdiv's face-varying linear
/// interpolation, 0 none .. 5 all (see [`crate::FVarLinearInterpolation`]).
fn fvar_option(args: &TagArgs<'_>, line: u32) -> Result<crate::FVarLinearInterpolation, MeshError> {
    args.ints
        .first()
        .and_then(|&k| crate::FVarLinearInterpolation::from_tag(k))
        .ok_or_else(|| {
            perr(
                line,
                format!(
                    "facevaryinginterpolateboundary: expected 0 (none) to 5 (all), got {:?}",
                    args.ints.first()
                ),
            )
        })
}

/// Why a tag named `name` (not one of the applied ones) is ignored.
fn ignored_kind(name: &str) -> IgnoredTagKind {
    match name {
        "vertexedit" | "edgeedit" | "faceedit" => IgnoredTagKind::HierarchicalEdit,
        n if n.starts_with("facevarying") => IgnoredTagKind::FaceVarying,
        _ => IgnoredTagKind::Unknown,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::obj::parse_obj;

    const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

    #[test]
    fn smoothtriangles_as_opensubdiv_spells_it() {
        let s = parse_obj(&format!("{QUAD}t smoothtriangles 0/0/1 smooth\n")).unwrap();
        assert_eq!(s.options.triangles, TriangleSubdivision::Smooth);
        assert!(s.warnings.is_empty());
        let s = parse_obj(&format!("{QUAD}t smoothtriangles 0/0/1 catmark\n")).unwrap();
        assert_eq!(s.options.triangles, TriangleSubdivision::Catmark);
        let s = parse_obj(&format!("{QUAD}t smoothtriangles 1/0/0 1\n")).unwrap();
        assert_eq!(s.options.triangles, TriangleSubdivision::Smooth);
        assert_eq!(
            parse_obj(QUAD).unwrap().options.triangles,
            TriangleSubdivision::Catmark
        );
        // Written back by the cage writer.
        let smooth = parse_obj(&format!("{QUAD}t smoothtriangles 0/0/1 smooth\n")).unwrap();
        let text = crate::format_mesh_obj(&crate::Mesh::from_soup(&smooth).unwrap());
        assert!(text.contains("t smoothtriangles 0/0/1 smooth\n"), "{text}");
        let e = parse_obj(&format!("{QUAD}t smoothtriangles 0/0/1 loop\n")).unwrap_err();
        assert_eq!(e.line(), Some(6));
        let e = parse_obj(&format!("{QUAD}t smoothtriangles 0/0/0\n")).unwrap_err();
        assert_eq!(e.line(), Some(6));
    }

    #[test]
    fn tags_not_applied_warn_with_their_lines() {
        let text = format!(
            "{QUAD}t bogustag 0/0/0\nt crease 2/1/0 0 1 2\nt vertexedit 1/3/2 0 1 2 3 value set\n\
             t facevaryingpropagatecorners 1/0/0 1\nt faceedit 0/0/0\nt edgeedit 0/0/0\n"
        );
        let s = parse_obj(&text).unwrap();
        let got: Vec<(u32, &str, IgnoredTagKind)> = s
            .warnings
            .iter()
            .map(|w| (w.line, w.name.as_str(), w.kind))
            .collect();
        assert_eq!(
            got,
            vec![
                (6, "bogustag", IgnoredTagKind::Unknown),
                (8, "vertexedit", IgnoredTagKind::HierarchicalEdit),
                (
                    9,
                    "facevaryingpropagatecorners",
                    IgnoredTagKind::FaceVarying
                ),
                (10, "faceedit", IgnoredTagKind::HierarchicalEdit),
                (11, "edgeedit", IgnoredTagKind::HierarchicalEdit),
            ]
        );
        // The applied crease is still there; the warnings name line and tag.
        assert_eq!(s.creases.len(), 1);
        assert_eq!(s.warnings[0].short(), "line 6: t bogustag");
        assert_eq!(
            s.warnings[1].to_string(),
            "8: tag 't vertexedit' ignored (hierarchical edits are not supported)"
        );
    }

    #[test]
    fn malformed_ignored_tags_are_errors_not_panics() {
        for bad in [
            "t vertexedit 2/0/0 1\n",
            "t bogus\n",
            "t bogus x/y/z\n",
            "t\n",
        ] {
            let e = parse_obj(&format!("{QUAD}{bad}")).unwrap_err();
            assert_eq!(e.line(), Some(6), "{bad}");
        }
    }
}
