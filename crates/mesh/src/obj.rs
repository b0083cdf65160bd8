//! Wavefront OBJ input and output, with OpenSubdiv's `t` tag lines.
//!
//! The reader keeps vertices in file order (a cage's vertex `i` stays vertex `i`, which the
//! OpenSubdiv reference data relies on) and remembers the line of every vertex, face and tag so
//! that every error names its line. It reads `v`, `f` (any of `i`, `i/t`, `i//n`, `i/t/n`,
//! negative indices), `g`/`o` (face groups), and the tags
//!
//! ```text
//! t crease n/1/0 v0 .. v(n-1) s        t crease n/(n-1)/0 v0 .. v(n-1) s0 .. s(n-2)
//! t corner n/1/0 v0 .. s               t corner n/n/0 v0 .. s0 ..
//! t hole n/0/0 f0 ..                   t interpolateboundary 1/0/0 k  (0 none, 1 edge-and-corner, 2 edge-only)
//! t creasemethod 0/0/1 chaikin|uniform     t smoothtriangles 0/0/1 smooth|catmark
//! ```
//!
//! `vt` lines with `f v/vt` or `f v/vt/vn` corners give the face-varying channel
//! ([`crate::FaceVarying`]; either every face has texture indices or none has), and
//! `t facevaryinginterpolateboundary 1/0/0 k` its linear interpolation option (0 none,
//! 1 cornersOnly, 2 cornersPlus1, 3 cornersPlus2, 4 boundaries, 5 all, as OpenSubdiv reads it).
//! Other statements (`vn`, `s`, `usemtl`, ...) are ignored. Other tag lines (unknown
//! names, OpenSubdiv's hierarchical edits such as `vertexedit`, other face-varying options) are not
//! applied: each leaves a [`TagWarning`] naming its line in [`PolygonSoup::warnings`] (see
//! [`read_obj_with_warnings`]).
//! (`tobj` is not used for reading: it renumbers vertices per object in order of first use and
//! reports errors without line numbers.)
//!
//! The writer prints `f32` coordinates with Rust's shortest round-trip formatting, so a written
//! file reads back bit-identical.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use glam::Vec3;

use crate::error::{MeshError, ObjError};
use crate::mesh::Mesh;
use crate::options::{
    BoundaryInterpolation, CreaseMethod, SHARPNESS_INFINITE, TriangleSubdivision,
};
use crate::soup::{NonManifold, PolygonSoup};
use crate::tags::{TagWarning, parse_tag};

/// Parses OBJ text into a polygon soup (no topology validation yet).
pub fn parse_obj(text: &str) -> Result<PolygonSoup, MeshError> {
    let mut soup = PolygonSoup::default();
    let mut current_group = u32::MAX;
    let mut colours: Vec<(usize, [f32; 3])> = Vec::new();
    for (ln, raw) in text.lines().enumerate() {
        let line = (ln + 1) as u32;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let mut toks = content.split_whitespace();
        let Some(kw) = toks.next() else { continue };
        let perr = |msg: String| MeshError::Parse { line, msg };
        match kw {
            "v" => {
                let mut c = [0.0f32; 3];
                for (k, slot) in c.iter_mut().enumerate() {
                    let t = toks
                        .next()
                        .ok_or_else(|| perr(format!("vertex needs 3 coordinates, found {k}")))?;
                    *slot = t
                        .parse::<f32>()
                        .map_err(|_| perr(format!("invalid coordinate '{t}'")))?;
                }
                soup.positions.push(Vec3::from(c));
                soup.vertex_lines.push(line);
                // `v x y z r g b`: a vertex colour (a fourth number alone is OBJ's weight).
                let rest: Vec<&str> = toks.collect();
                if rest.len() == 3 {
                    let mut rgb = [0.0f32; 3];
                    for (slot, t) in rgb.iter_mut().zip(&rest) {
                        *slot = t
                            .parse::<f32>()
                            .ok()
                            .filter(|x| x.is_finite())
                            .ok_or_else(|| perr(format!("invalid vertex colour '{t}'")))?;
                    }
                    colours.push((soup.positions.len() - 1, rgb));
                }
            }
            "vt" => {
                let mut c = [0.0f32; 2];
                for (k, slot) in c.iter_mut().enumerate() {
                    let t = toks.next().ok_or_else(|| {
                        perr(format!("texture vertex needs 2 coordinates, found {k}"))
                    })?;
                    *slot = t
                        .parse::<f32>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| perr(format!("invalid texture coordinate '{t}'")))?;
                }
                soup.uvs.push(glam::Vec2::from(c));
            }
            "f" => {
                let face = soup.num_faces();
                let (idx, uv) = parse_face(toks, soup.positions.len(), soup.uvs.len(), line)?;
                // The first face decides whether faces carry `vt`.
                let with_uv = if face == 0 {
                    uv.is_some()
                } else {
                    !soup.uv_indices.is_empty()
                };
                match (uv, with_uv) {
                    (Some(uv), true) => soup.uv_indices.extend(uv),
                    (None, false) => {}
                    (Some(_), false) => {
                        return Err(perr(format!(
                            "face {face} has texture indices (v/vt) but earlier faces have none"
                        )));
                    }
                    (None, true) => {
                        return Err(perr(format!(
                            "face {face} has no texture indices (v/vt) but earlier faces have them"
                        )));
                    }
                }
                soup.push_face(idx);
                soup.face_lines.push(line);
                soup.face_groups.push(current_group);
            }
            "g" | "o" => {
                let name: Vec<&str> = toks.collect();
                let name = if name.is_empty() {
                    "default".to_string()
                } else {
                    name.join(" ")
                };
                current_group = match soup.groups.iter().position(|g| *g == name) {
                    Some(i) => i as u32,
                    None => {
                        soup.groups.push(name);
                        (soup.groups.len() - 1) as u32
                    }
                };
            }
            "t" => parse_tag(&mut soup, toks.collect(), line)?,
            _ => {}
        }
    }
    if soup.groups.is_empty() {
        soup.face_groups.clear();
    }
    vertex_colours(&mut soup, colours)?;
    Ok(soup)
}

/// The vertex colours of `v x y z r g b` lines as the primvar `displayColor` (vertex, width
/// 3): every vertex has one, or none has (a vertex without one is an error naming its line).
fn vertex_colours(
    soup: &mut PolygonSoup,
    colours: Vec<(usize, [f32; 3])>,
) -> Result<(), MeshError> {
    if colours.is_empty() {
        return Ok(());
    }
    if colours.len() != soup.positions.len() {
        let mut has = vec![false; soup.positions.len()];
        for &(v, _) in &colours {
            has[v] = true;
        }
        let v = has.iter().position(|&h| !h).unwrap_or(0);
        return Err(MeshError::Parse {
            line: soup.vertex_lines.get(v).copied().unwrap_or(0),
            msg: format!(
                "vertex {} has no colour, but {} vertices have one (v x y z r g b on every vertex line, or on none)",
                v + 1,
                colours.len()
            ),
        });
    }
    soup.primvars.push(crate::Primvar {
        name: "displayColor".into(),
        interpolation: crate::PrimvarInterpolation::Vertex,
        width: 3,
        values: colours.iter().flat_map(|(_, c)| *c).collect(),
        indices: (0..colours.len() as u32).collect(),
    });
    Ok(())
}

/// Resolves a 1-based or negative (relative) OBJ index against `count` elements; 0 is refused.
fn obj_index(t: &str, count: usize, what: &str, line: u32) -> Result<i64, MeshError> {
    let perr = |msg: String| MeshError::Parse { line, msg };
    let i: i64 = t
        .parse()
        .map_err(|_| perr(format!("invalid {what} index '{t}'")))?;
    match i {
        0 => Err(perr(format!(
            "{what} index 0 is invalid (OBJ indices start at 1)"
        ))),
        i if i > 0 => Ok(i - 1),
        i => Ok(count as i64 + i),
    }
}

/// The vertex indices of an `f` line and, when every corner has one (`v/vt`, `v/vt/vn`), its
/// texture indices. A texture index outside the `vt` lines read so far is an error naming the
/// line; corners that mix `v` and `v/vt` are too.
fn parse_face<'a>(
    toks: impl Iterator<Item = &'a str>,
    nv: usize,
    nvt: usize,
    line: u32,
) -> Result<(Vec<i64>, Option<Vec<i64>>), MeshError> {
    let perr = |msg: String| MeshError::Parse { line, msg };
    let mut idx = Vec::new();
    let mut uv = Vec::new();
    let mut corners_with_uv = 0;
    for t in toks {
        let mut parts = t.split('/');
        idx.push(obj_index(parts.next().unwrap_or(""), nv, "face", line)?);
        if let Some(vt) = parts.next().filter(|s| !s.is_empty()) {
            let k = obj_index(vt, nvt, "texture", line)?;
            if k < 0 || k >= nvt as i64 {
                return Err(perr(format!(
                    "texture index {vt} in '{t}' is out of range ({nvt} vt lines before it)"
                )));
            }
            uv.push(k);
            corners_with_uv += 1;
        }
    }
    match corners_with_uv {
        0 => Ok((idx, None)),
        n if n == idx.len() => Ok((idx, Some(uv))),
        _ => Err(perr(
            "some corners of the face have a texture index (v/vt) and some not".into(),
        )),
    }
}

/// Reads an OBJ file and builds a validated mesh.
///
/// ```no_run
/// let mesh = subdiv_mesh::read_obj("cage.obj").unwrap();
/// println!("{} faces", mesh.num_faces());
/// ```
pub fn read_obj(path: impl AsRef<Path>) -> Result<Mesh, ObjError> {
    read_obj_with(path, ReadOptions::default())
}

/// Options of [`read_obj_with`].
#[derive(Clone, Copy, Debug, Default)]
pub struct ReadOptions {
    /// Repair vertices where several fans of faces meet by giving each fan its own copy (see
    /// [`PolygonSoup::split_nonmanifold_vertices`]; the surface opens there) instead of
    /// refining non-manifold cages as OpenSubdiv does ([`PolygonSoup::split_nonmanifold`]).
    pub split_nonmanifold_vertices: bool,
}

/// Reads an OBJ file with options and builds a validated mesh.
pub fn read_obj_with(path: impl AsRef<Path>, opts: ReadOptions) -> Result<Mesh, ObjError> {
    Ok(read_obj_with_warnings(path, opts)?.0)
}

/// [`read_obj_with`], also returning the tag lines that were read but not applied (unknown
/// tags, hierarchical edits, face-varying options), in file order.
pub fn read_obj_with_warnings(
    path: impl AsRef<Path>,
    opts: ReadOptions,
) -> Result<(Mesh, Vec<TagWarning>), ObjError> {
    let (mesh, warnings, _) = read_obj_with_report(path, opts)?;
    Ok((mesh, warnings))
}

/// [`read_obj_with_warnings`], also returning what was non-manifold (see
/// [`PolygonSoup::split_nonmanifold`]; empty with `split_nonmanifold_vertices`).
pub fn read_obj_with_report(
    path: impl AsRef<Path>,
    opts: ReadOptions,
) -> Result<(Mesh, Vec<TagWarning>, NonManifold), ObjError> {
    let path = path.as_ref();
    let mut soup = read_obj_soup(path)?;
    let invalid = |err| ObjError::Invalid {
        path: path.display().to_string(),
        err,
    };
    let found = soup
        .prepare_nonmanifold(opts.split_nonmanifold_vertices)
        .map_err(invalid)?;
    let mesh = Mesh::from_soup(&soup).map_err(invalid)?;
    Ok((mesh, soup.warnings, found))
}

/// Reads an OBJ file into a polygon soup, without topology validation.
pub fn read_obj_soup(path: impl AsRef<Path>) -> Result<PolygonSoup, ObjError> {
    let path = path.as_ref();
    let p = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| ObjError::Io {
        path: p.clone(),
        source,
    })?;
    let text = String::from_utf8_lossy(&bytes);
    parse_obj(&text).map_err(|err| ObjError::Invalid { path: p, err })
}

/// Surface data to write as OBJ: positions, optional normals (one per position, and one-sided
/// normals of some face corners) and polygons.
#[derive(Clone, Copy, Debug)]
pub struct ObjData<'a> {
    /// Vertex positions.
    pub positions: &'a [[f32; 3]],
    /// Optional per-vertex normals.
    pub normals: Option<&'a [[f32; 3]]>,
    /// Face start offsets into `face_indices`, one per face plus a final end.
    pub face_offsets: &'a [u32],
    /// 0-based vertex indices.
    pub face_indices: &'a [u32],
    /// Normals of single face corners (index into `face_indices`, ascending), written as their
    /// own `vn` after the per-vertex ones; only with `normals`.
    pub corner_normals: &'a [(u32, [f32; 3])],
    /// Texture coordinates, written as `vt`; see `uv_indices`.
    pub uvs: &'a [[f32; 2]],
    /// The texture coordinate of every face corner (aligned with `face_indices`), written as
    /// `f v/vt` or `f v/vt/vn`; empty: no texture coordinates.
    pub uv_indices: &'a [u32],
    /// Vertex colours, three floats per vertex, written as `v x y z r g b`.
    pub colours: Option<&'a [f32]>,
}

/// Formats surface data as OBJ text.
pub fn format_obj(data: &ObjData<'_>) -> String {
    let mut s = String::with_capacity(data.positions.len() * 40 + data.face_indices.len() * 8);
    for (i, p) in data.positions.iter().enumerate() {
        match data.colours.and_then(|c| c.get(3 * i..3 * i + 3)) {
            Some(c) => {
                let _ = writeln!(s, "v {} {} {} {} {} {}", p[0], p[1], p[2], c[0], c[1], c[2]);
            }
            None => {
                let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
            }
        }
    }
    let mut corner_normals: &[(u32, [f32; 3])] = &[];
    if let Some(ns) = data.normals {
        corner_normals = data.corner_normals;
        for n in ns.iter().chain(corner_normals.iter().map(|(_, n)| n)) {
            let _ = writeln!(s, "vn {} {} {}", n[0], n[1], n[2]);
        }
    }
    let with_uv = !data.uv_indices.is_empty();
    if with_uv {
        for t in data.uvs {
            let _ = writeln!(s, "vt {} {}", t[0], t[1]);
        }
    }
    // 1-based `vn` of the next corner normal.
    let mut next_vn = data.normals.map_or(0, <[_]>::len) + 1;
    for w in data.face_offsets.windows(2) {
        s.push('f');
        for c in w[0]..w[1] {
            let i = data.face_indices[c as usize] as usize;
            let _ = write!(s, " {}", i + 1);
            if with_uv {
                let _ = write!(s, "/{}", data.uv_indices[c as usize] + 1);
            }
            if data.normals.is_none() {
                continue;
            }
            let slash = if with_uv { "/" } else { "//" };
            if corner_normals.first().is_some_and(|&(k, _)| k == c) {
                let _ = write!(s, "{slash}{next_vn}");
                corner_normals = &corner_normals[1..];
                next_vn += 1;
            } else {
                let _ = write!(s, "{slash}{}", i + 1);
            }
        }
        s.push('\n');
    }
    s
}

/// Writes surface data to an OBJ file.
pub fn write_obj(path: impl AsRef<Path>, data: &ObjData<'_>) -> Result<(), ObjError> {
    write_text(path.as_ref(), &format_obj(data))
}

fn write_text(path: &Path, text: &str) -> Result<(), ObjError> {
    let io = |source| ObjError::Io {
        path: path.display().to_string(),
        source,
    };
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
    f.write_all(text.as_bytes()).map_err(io)?;
    f.flush().map_err(io)
}

/// Formats a mesh as an OBJ cage, with groups, OpenSubdiv tags, UVs and vertex colours (a
/// vertex `displayColor` of 3 floats), so that reading it back gives the same mesh (but for its
/// other primvars, which OBJ cannot hold).
pub fn format_mesh_obj(mesh: &Mesh) -> String {
    let mut s = String::new();
    // OBJ's vertex colours: a display colour of 3 floats a vertex.
    let colour = mesh
        .primvar("displayColor")
        .filter(|p| p.interpolation == crate::PrimvarInterpolation::Vertex && p.width == 3);
    for (v, p) in mesh.positions().iter().enumerate() {
        match colour {
            Some(c) => {
                let [r, g, b] = [0, 1, 2].map(|k| c.element(v)[k]);
                let _ = writeln!(s, "v {} {} {} {r} {g} {b}", p.x, p.y, p.z);
            }
            None => {
                let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
            }
        }
    }
    if let Some(fv) = mesh.uv() {
        for t in &fv.values {
            let _ = writeln!(s, "vt {} {}", t.x, t.y);
        }
    }
    let mut group = u32::MAX;
    let (offsets, _) = mesh.face_lists();
    for f in mesh.faces() {
        let g = mesh.face_group(f);
        if g != group && (g as usize) < mesh.groups().len() {
            let _ = writeln!(s, "g {}", mesh.groups()[g as usize]);
            group = g;
        }
        s.push('f');
        for (k, v) in mesh.face_vertices(f).iter().enumerate() {
            match mesh.uv() {
                Some(fv) => {
                    let t = fv.indices[offsets[f.idx()] as usize + k];
                    let _ = write!(s, " {}/{}", v.0 + 1, t + 1);
                }
                None => {
                    let _ = write!(s, " {}", v.0 + 1);
                }
            }
        }
        s.push('\n');
    }
    let opts = mesh.options();
    let ib = match opts.boundary {
        BoundaryInterpolation::None => 0,
        BoundaryInterpolation::EdgeAndCorner => 1,
        BoundaryInterpolation::EdgeOnly => 2,
    };
    let _ = writeln!(s, "t interpolateboundary 1/0/0 {ib}");
    if opts.crease == CreaseMethod::Chaikin {
        let _ = writeln!(s, "t creasemethod 0/0/1 chaikin");
    }
    if opts.triangles == TriangleSubdivision::Smooth {
        let _ = writeln!(s, "t smoothtriangles 0/0/1 smooth");
    }
    if opts.fvar != crate::FVarLinearInterpolation::default() {
        let _ = writeln!(
            s,
            "t facevaryinginterpolateboundary 1/0/0 {}",
            opts.fvar.tag()
        );
    }
    for e in mesh.edges() {
        let sh = mesh.edge_sharpness(e);
        if sh > 0.0 && !mesh.is_boundary_edge(e) {
            let [a, b] = mesh.edge_vertices(e);
            let _ = writeln!(s, "t crease 2/1/0 {} {} {}", a.0, b.0, sh);
        }
    }
    for v in mesh.vertices() {
        let sh = mesh.vertex_sharpness(v);
        let implied = opts.boundary == BoundaryInterpolation::EdgeAndCorner
            && sh >= SHARPNESS_INFINITE
            && mesh.is_boundary_vertex(v)
            && mesh.valence(v) == 2;
        if sh > 0.0 && !implied {
            let _ = writeln!(s, "t corner 1/1/0 {} {}", v.0, sh);
        }
    }
    for f in mesh.faces() {
        if mesh.is_hole(f) {
            let _ = writeln!(s, "t hole 1/0/0 {}", f.0);
        }
    }
    s
}

/// Writes a mesh as an OBJ cage with its tags (see [`format_mesh_obj`]).
pub fn write_mesh_obj(path: impl AsRef<Path>, mesh: &Mesh) -> Result<(), ObjError> {
    write_text(path.as_ref(), &format_mesh_obj(mesh))
}

#[cfg(test)]
#[path = "obj_tests.rs"]
mod tests;
