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
use crate::soup::PolygonSoup;
use crate::tags::{TagWarning, parse_tag};

/// Parses OBJ text into a polygon soup (no topology validation yet).
pub fn parse_obj(text: &str) -> Result<PolygonSoup, MeshError> {
    let mut soup = PolygonSoup::default();
    let mut current_group = u32::MAX;
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
    Ok(soup)
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
    /// [`PolygonSoup::split_nonmanifold_vertices`]) instead of refusing the mesh.
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
    let path = path.as_ref();
    let mut soup = read_obj_soup(path)?;
    if opts.split_nonmanifold_vertices {
        soup.split_nonmanifold_vertices();
    }
    let mesh = Mesh::from_soup(&soup).map_err(|err| ObjError::Invalid {
        path: path.display().to_string(),
        err,
    })?;
    Ok((mesh, soup.warnings))
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
}

/// Formats surface data as OBJ text.
pub fn format_obj(data: &ObjData<'_>) -> String {
    let mut s = String::with_capacity(data.positions.len() * 40 + data.face_indices.len() * 8);
    for p in data.positions {
        let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
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

/// Formats a mesh as an OBJ cage, with groups and OpenSubdiv tags, so that reading it back gives
/// the same mesh.
pub fn format_mesh_obj(mesh: &Mesh) -> String {
    let mut s = String::new();
    for p in mesh.positions() {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
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
mod tests {
    use super::*;
    use crate::handle::{FaceId, VertexId};

    const CUBE: &str = "# cube\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
g lid\nf 1 3 4 2\nf 5//1 6//2 8//3 7//4\ng sides\nf 1//1 2//1 6//1 5//1\nf 3 7 8 4\nf 1 5 7 3\nf -7 -5 -1 -3\n\
t crease 3/1/0 0 2 3 2.5\nt corner 1/1/0 7 4\nt hole 1/0/0 1\nt creasemethod 0/0/1 chaikin\n";

    #[test]
    fn parses_cube_with_tags() {
        let soup = parse_obj(CUBE).unwrap();
        assert_eq!(soup.positions.len(), 8);
        assert_eq!(soup.num_faces(), 6);
        assert_eq!(soup.face(5), &[1, 3, 7, 5]);
        assert_eq!(soup.groups, vec!["lid".to_string(), "sides".to_string()]);
        assert_eq!(soup.face_groups, vec![0, 0, 1, 1, 1, 1]);
        assert_eq!(soup.face_lines[0], 11);
        let m = Mesh::from_soup(&soup).unwrap();
        assert_eq!(m.options().crease, CreaseMethod::Chaikin);
        let e = m.find_halfedge(VertexId(2), VertexId(3)).unwrap().edge();
        assert_eq!(m.edge_sharpness(e), 2.5);
        assert_eq!(m.vertex_sharpness(VertexId(7)), 4.0);
        assert!(m.is_hole(FaceId(1)));
    }

    const UV_QUADS: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n\
vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 0.6 0\nvt 1 0\nvt 1 1\nvt 0.6 1\n";

    #[test]
    fn texture_coordinates_make_a_face_varying_channel_with_seams() {
        // Two quads sharing the edge 2-3, with different vt on each side: a seam.
        let text = format!(
            "{UV_QUADS}f 1/1 2/2 3/3 4/4\nf 2/5/1 5/6/1 6/-2/1 3/-1/1\n\
             t facevaryinginterpolateboundary 1/0/0 4\n"
        );
        let m = Mesh::from_soup(&parse_obj(&text).unwrap()).unwrap();
        let fv = m.uv().unwrap();
        assert_eq!(fv.values.len(), 8);
        assert_eq!(fv.indices, vec![0, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(fv.corner(6), glam::Vec2::new(1.0, 1.0));
        assert_eq!(m.options().fvar, crate::FVarLinearInterpolation::Boundaries);
        // The cage writer keeps the channel and the option.
        let back = Mesh::from_soup(&parse_obj(&format_mesh_obj(&m)).unwrap()).unwrap();
        assert_eq!(back.uv(), m.uv());
        assert_eq!(back.options().fvar, m.options().fvar);
        // Without vt the mesh has no channel.
        assert!(
            Mesh::from_soup(&parse_obj(CUBE).unwrap())
                .unwrap()
                .uv()
                .is_none()
        );
    }

    #[test]
    fn bad_texture_indices_are_errors_with_their_line() {
        let cases = [
            ("f 1/1 2/2 3/9 4/4\n", 15, "texture index 9"),
            ("f 1/1 2/2 3/0 4/4\n", 15, "texture index 0"),
            ("f 1/1 2/-9 3/3 4/4\n", 15, "texture index -9"),
            ("f 1/1 2/x 3/3 4/4\n", 15, "invalid texture index 'x'"),
            ("f 1/1 2 3/3 4/4\n", 15, "some corners"),
            (
                "f 1/1 2/2 3/3 4/4\nf 2 5 6 3\n",
                16,
                "face 1 has no texture",
            ),
            ("f 1 2 3 4\nf 2/5 5/6 6/7 3/8\n", 16, "face 1 has texture"),
            (
                "t facevaryinginterpolateboundary 1/0/0 6\n",
                15,
                "0 (none) to 5 (all)",
            ),
        ];
        for (tail, line, what) in cases {
            let e = parse_obj(&format!("{UV_QUADS}{tail}")).unwrap_err();
            assert_eq!(e.line(), Some(line), "{tail}: {e}");
            assert!(e.to_string().contains(what), "{tail}: {e}");
        }
        let e = parse_obj("v 0 0 0\nvt 0 nan\n").unwrap_err();
        assert_eq!(e.line(), Some(2), "{e}");
        // A soup made in code is checked when the mesh is built.
        let mut soup = parse_obj(&format!("{UV_QUADS}f 1/1 2/2 3/3 4/4\n")).unwrap();
        soup.uv_indices[2] = 8;
        let e = Mesh::from_soup(&soup).unwrap_err();
        assert!(
            matches!(
                e,
                MeshError::UvIndexOutOfRange {
                    face: 0,
                    vertex: 2,
                    index: 8,
                    count: 8,
                    line: Some(15)
                }
            ),
            "{e:?}"
        );
        soup.uv_indices.pop();
        assert!(matches!(
            Mesh::from_soup(&soup).unwrap_err(),
            MeshError::UvCount { .. }
        ));
    }

    #[test]
    fn cage_round_trip_is_exact() {
        let m = Mesh::from_soup(&parse_obj(CUBE).unwrap()).unwrap();
        let text = format_mesh_obj(&m);
        let m2 = Mesh::from_soup(&parse_obj(&text).unwrap()).unwrap();
        assert_eq!(m.positions(), m2.positions());
        assert_eq!(m.edge_sharpnesses(), m2.edge_sharpnesses());
        assert_eq!(m.vertex_sharpnesses(), m2.vertex_sharpnesses());
        assert_eq!(m.holes(), m2.holes());
        assert_eq!(m.groups(), m2.groups());
        assert_eq!(m.face_groups(), m2.face_groups());
    }

    #[test]
    fn written_floats_reread_bit_identical() {
        let vals = [
            0.1f32,
            1.0 / 3.0,
            -7.654321e-12,
            3.4028235e38,
            1.0e-45,
            123456.79,
        ];
        let pos: Vec<[f32; 3]> = vals.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        let text = format_obj(&ObjData {
            positions: &pos,
            normals: Some(&pos),
            face_offsets: &[0, 2, 4],
            face_indices: &[0, 1, 1, 0],
            corner_normals: &[(1, [0.1, -1.0 / 3.0, 0.9]), (3, pos[1])],
            uvs: &[],
            uv_indices: &[],
        });
        let soup = parse_obj(&text).unwrap();
        for (a, b) in pos.iter().zip(&soup.positions) {
            assert_eq!(a.map(f32::to_bits), b.to_array().map(f32::to_bits));
        }
        assert!(text.contains("f 1//1 2//3\nf 2//2 1//4\n"), "{text}");
        // The corner normals follow the vertex normals, exact.
        let vn: Vec<[f32; 3]> = text
            .lines()
            .filter_map(|l| l.strip_prefix("vn "))
            .map(|l| {
                let v: Vec<f32> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                [v[0], v[1], v[2]]
            })
            .collect();
        assert_eq!(vn.len(), 4);
        assert_eq!(
            vn[2].map(f32::to_bits),
            [0.1f32, -1.0 / 3.0, 0.9].map(f32::to_bits)
        );
        assert_eq!(vn[3], pos[1]);

        // With texture coordinates: `v/vt/vn` corners, and the `vt` re-read bit-identical.
        let uvs = [[0.25f32, 1.0 / 3.0], [7.654321e-12, 1.0]];
        let text = format_obj(&ObjData {
            positions: &pos,
            normals: Some(&pos),
            face_offsets: &[0, 2, 4],
            face_indices: &[0, 1, 1, 0],
            corner_normals: &[(1, [0.1, -1.0 / 3.0, 0.9])],
            uvs: &uvs,
            uv_indices: &[1, 0, 0, 1],
        });
        assert!(text.contains("f 1/2/1 2/1/3\nf 2/1/2 1/2/1\n"), "{text}");
        let soup = parse_obj(&text).unwrap();
        assert_eq!(soup.uv_indices, vec![1, 0, 0, 1]);
        for (a, b) in uvs.iter().zip(&soup.uvs) {
            assert_eq!(a.map(f32::to_bits), b.to_array().map(f32::to_bits));
        }
        // Without normals: `v/vt`.
        let text = format_obj(&ObjData {
            positions: &pos,
            normals: None,
            face_offsets: &[0, 2, 4],
            face_indices: &[0, 1, 1, 0],
            corner_normals: &[],
            uvs: &uvs,
            uv_indices: &[1, 0, 0, 1],
        });
        assert!(text.contains("f 1/2 2/1\n"), "{text}");
    }

    #[test]
    fn parse_errors_name_lines() {
        let e = parse_obj("v 0 0 0\nv 1 x 0\n").unwrap_err();
        assert_eq!(e.line(), Some(2));
        let e = parse_obj("v 0 0\n").unwrap_err();
        assert_eq!(e.line(), Some(1));
        let e = parse_obj("v 0 0 0\nf 1 0 1\n").unwrap_err();
        assert!(matches!(e, MeshError::Parse { line: 2, .. }));
        let e = parse_obj("t crease 2/1/0 0 1\n").unwrap_err();
        assert!(matches!(e, MeshError::Parse { line: 1, .. }));
        let e = parse_obj("t crease 3/2/0 0 1 2 1\n").unwrap_err();
        assert!(matches!(e, MeshError::Parse { line: 1, .. }), "{e:?}");
        // Validation errors carry the face's line.
        let soup = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n").unwrap();
        let e = Mesh::from_soup(&soup).unwrap_err();
        assert_eq!(e.line(), Some(5));
        assert!(matches!(e, MeshError::IndexOutOfRange { index: 3, .. }));
    }

    #[test]
    fn tag_counts_that_overflow_are_parse_errors() {
        // Found by fuzzing: these counts wrapped around to the number of arguments and the
        // argument slices panicked.
        for text in [
            "t crease 18446744073709551615/1/0\n",
            "t crease 18446744073709551615/18446744073709551615/2 1 2\n",
            "v 0 0 0\nt corner 9223372036854775808/9223372036854775808/0\n",
        ] {
            let e = parse_obj(text).unwrap_err();
            assert!(matches!(e, MeshError::Parse { .. }), "{text}: {e:?}");
            assert_eq!(e.line(), Some(text.lines().count() as u32), "{text}");
            assert!(e.to_string().contains("announce too many arguments"), "{e}");
        }
    }

    #[test]
    fn obj_error_display_has_file_and_line() {
        let dir = std::env::temp_dir().join(format!("subdiv-mesh-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("bad.obj");
        std::fs::write(&p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n").unwrap();
        let e = read_obj(&p).unwrap_err().to_string();
        assert!(
            e.ends_with("bad.obj:4: face 0 uses vertex 1 more than once (degenerate face)"),
            "{e}"
        );
        let e = read_obj(dir.join("missing.obj")).unwrap_err();
        assert!(matches!(e, ObjError::Io { .. }));
        // The cause is printed once: by `source()`, not repeated in the message.
        let cause = std::error::Error::source(&e).expect("the I/O error is the source");
        assert!(e.to_string().ends_with("missing.obj"), "{e}");
        assert!(!e.to_string().contains(&cause.to_string()), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
