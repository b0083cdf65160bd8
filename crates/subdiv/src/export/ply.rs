//! Binary little-endian PLY output: vertices (position, normal, optional `s t`, optional scalar,
//! optional parameter point `face u v`)
//! and triangles (`list uchar uint vertex_indices`).

use std::fmt::Write as _;
use std::path::Path;

use subdiv_rules::LimitMesh;

use super::{ExportError, vertex_uvs, write_file};

/// Writes `s` (checked) as binary little-endian PLY.
pub(super) fn write(path: &Path, s: &LimitMesh) -> Result<(), ExportError> {
    let n = s.positions().len();
    let mut head = String::from("ply\nformat binary_little_endian 1.0\ncomment made by subdiv\n");
    let _ = writeln!(head, "element vertex {n}");
    for p in ["x", "y", "z", "nx", "ny", "nz"] {
        let _ = writeln!(head, "property float {p}");
    }
    if vertex_uvs(s).is_some() {
        head.push_str("property float s\nproperty float t\n");
    }
    let mut channel_floats = 0;
    for c in s.channels() {
        for p in super::ply_properties(&c.name, c.width) {
            let _ = writeln!(head, "property float {p}");
        }
        channel_floats += c.width;
    }
    if let Some((kind, _)) = s.scalar() {
        let _ = writeln!(head, "property float {}", kind.ply_property());
    }
    if s.params().is_some() {
        head.push_str("property uint face\nproperty float u\nproperty float v\n");
    }
    let _ = writeln!(head, "element face {}", s.face_indices().len() / 3);
    head.push_str("property list uchar uint vertex_indices\nend_header\n");
    let floats = 6
        + if vertex_uvs(s).is_some() { 2 } else { 0 }
        + channel_floats
        + usize::from(s.scalar().is_some());
    let mut out = Vec::with_capacity(head.len() + n * floats * 4 + s.face_indices().len() / 3 * 13);
    out.extend_from_slice(head.as_bytes());
    for i in 0..n {
        let mut put = |x: f32| out.extend_from_slice(&x.to_le_bytes());
        s.positions()[i].into_iter().for_each(&mut put);
        s.normals()[i].into_iter().for_each(&mut put);
        if let Some(uv) = vertex_uvs(s) {
            uv[i].into_iter().for_each(&mut put);
        }
        for c in s.channels() {
            c.value(i).iter().copied().for_each(&mut put);
        }
        if let Some((_, v)) = s.scalar() {
            put(v[i]);
        }
        if let Some(p) = s.params() {
            out.extend_from_slice(&p.face[i].to_le_bytes());
            out.extend_from_slice(&p.uv[i][0].to_le_bytes());
            out.extend_from_slice(&p.uv[i][1].to_le_bytes());
        }
    }
    for t in s.face_indices().chunks_exact(3) {
        out.push(3);
        for &i in t {
            out.extend_from_slice(&i.to_le_bytes());
        }
    }
    write_file(path, &out)
}
