//! glTF 2.0 output (`.gltf` + `.bin`, or `.glb`): one mesh, one triangle primitive, one node.

use std::collections::BTreeMap;
use std::path::Path;

use gltf_json as json;
use json::accessor::{ComponentType, GenericComponentType, Type};
use json::buffer::Target;
use json::mesh::{Mode, Semantic};
use json::validation::Checked::Valid;
use json::validation::USize64;

use subdiv_rules::LimitMesh;

use super::{ExportError, vertex_uvs, write_file};

/// Writes `s` (checked) as glTF; `binary` for `.glb`, else JSON with the data in `STEM.bin`.
pub(super) fn write(path: &Path, s: &LimitMesh, binary: bool) -> Result<(), ExportError> {
    let file = path.display().to_string();
    let mut root = json::Root::default();
    root.asset.generator = Some(format!("subdiv {}", env!("CARGO_PKG_VERSION")));
    let mut bin = Vec::new();
    let mut attributes = BTreeMap::new();
    let pos = push_floats(&mut root, &mut bin, s.positions(), Type::Vec3);
    attributes.insert(Valid(Semantic::Positions), pos);
    let nrm = push_floats(&mut root, &mut bin, s.normals(), Type::Vec3);
    attributes.insert(Valid(Semantic::Normals), nrm);
    if let Some(uv) = vertex_uvs(s) {
        let a = push_floats(&mut root, &mut bin, uv, Type::Vec2);
        attributes.insert(Valid(Semantic::TexCoords(0)), a);
    }
    for (attr, i, first, n) in super::gltf_attributes(s) {
        let c = &s.channels()[i];
        let rows = (0..c.num_values()).map(|v| &c.value(v)[first..first + n]);
        let a = match n {
            1 => push_floats(
                &mut root,
                &mut bin,
                &rows.map(|r| [r[0]]).collect::<Vec<_>>(),
                Type::Scalar,
            ),
            2 => push_floats(
                &mut root,
                &mut bin,
                &rows.map(|r| [r[0], r[1]]).collect::<Vec<_>>(),
                Type::Vec2,
            ),
            3 => push_floats(
                &mut root,
                &mut bin,
                &rows.map(|r| [r[0], r[1], r[2]]).collect::<Vec<_>>(),
                Type::Vec3,
            ),
            _ => push_floats(
                &mut root,
                &mut bin,
                &rows.map(|r| [r[0], r[1], r[2], r[3]]).collect::<Vec<_>>(),
                Type::Vec4,
            ),
        };
        let semantic = match attr {
            super::ChannelAttribute::Color => Semantic::Colors(0),
            super::ChannelAttribute::TexCoord(k) => Semantic::TexCoords(k as u32),
            super::ChannelAttribute::Custom(name) => Semantic::Extras(name),
        };
        attributes.insert(Valid(semantic), a);
    }
    if let Some((kind, values)) = s.scalar() {
        let one: Vec<[f32; 1]> = values.iter().map(|&v| [v]).collect();
        let a = push_floats(&mut root, &mut bin, &one, Type::Scalar);
        // `Extras(name)` is written `_name`: application-specific attributes start with `_`.
        let name = kind.gltf_attribute().trim_start_matches('_').to_string();
        attributes.insert(Valid(Semantic::Extras(name)), a);
    }
    if let Some(p) = s.params() {
        // glTF vertex attributes are floats: faces exactly up to 2^24.
        let face: Vec<[f32; 1]> = p.face.iter().map(|&f| [f as f32]).collect();
        let a = push_floats(&mut root, &mut bin, &face, Type::Scalar);
        attributes.insert(Valid(Semantic::Extras("FACE".into())), a);
        let a = push_floats(&mut root, &mut bin, &p.uv, Type::Vec2);
        attributes.insert(Valid(Semantic::Extras("PATCH_UV".into())), a);
    }
    let indices = push_indices(&mut root, &mut bin, s.face_indices());
    let sidecar = path.with_extension("bin");
    if !binary {
        let name = sidecar.file_name().and_then(|n| n.to_str());
        let name = name.ok_or_else(|| ExportError::Invalid {
            path: file.clone(),
            what: "the file name is not UTF-8".into(),
        })?;
        root.buffers[0].uri = Some(name.to_string());
    }
    root.buffers[0].byte_length = USize64::from(bin.len());
    let mesh = root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some("subdiv".into()),
        primitives: vec![json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: None,
            mode: Valid(Mode::Triangles),
            targets: None,
        }],
        weights: None,
    });
    let node = root.push(json::Node {
        mesh: Some(mesh),
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    root.scene = Some(scene);
    let text = json::serialize::to_string(&root).map_err(|e| ExportError::Invalid {
        path: file.clone(),
        what: format!("serializing glTF JSON: {e}"),
    })?;
    if binary {
        write_file(path, &glb(text.into_bytes(), bin, &file)?)
    } else {
        write_file(&sidecar, &bin)?;
        write_file(path, text.as_bytes())
    }
}

/// Appends `bytes` (4-byte aligned) to the one buffer as a view of its own.
fn push_view(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    bytes: &[u8],
    target: Target,
) -> json::Index<json::buffer::View> {
    if root.buffers.is_empty() {
        root.push(json::Buffer {
            byte_length: USize64(0),
            extensions: None,
            extras: Default::default(),
            name: None,
            uri: None,
        });
    }
    bin.resize(bin.len().next_multiple_of(4), 0);
    let offset = bin.len();
    bin.extend_from_slice(bytes);
    root.push(json::buffer::View {
        buffer: json::Index::new(0),
        byte_length: USize64::from(bytes.len()),
        byte_offset: Some(USize64::from(offset)),
        byte_stride: None,
        extensions: None,
        extras: Default::default(),
        name: None,
        target: Some(Valid(target)),
    })
}

/// A tightly packed `f32` vertex attribute of `N` components, with its bounds.
fn push_floats<const N: usize>(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    data: &[[f32; N]],
    type_: Type,
) -> json::Index<json::Accessor> {
    let mut bytes = Vec::with_capacity(data.len() * N * 4);
    let (mut lo, mut hi) = ([f32::INFINITY; N], [f32::NEG_INFINITY; N]);
    for v in data {
        for k in 0..N {
            bytes.extend_from_slice(&v[k].to_le_bytes());
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    let view = push_view(root, bin, &bytes, Target::ArrayBuffer);
    let bound = |b: [f32; N]| (!data.is_empty()).then(|| json::Value::from(b.to_vec()));
    root.push(json::Accessor {
        buffer_view: Some(view),
        byte_offset: Some(USize64(0)),
        count: USize64::from(data.len()),
        component_type: Valid(GenericComponentType(ComponentType::F32)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(type_),
        min: bound(lo),
        max: bound(hi),
        name: None,
        normalized: false,
        sparse: None,
    })
}

/// The triangle indices as `u32`, with their bounds.
fn push_indices(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    tris: &[u32],
) -> json::Index<json::Accessor> {
    let bytes: Vec<u8> = tris.iter().flat_map(|i| i.to_le_bytes()).collect();
    let view = push_view(root, bin, &bytes, Target::ElementArrayBuffer);
    let bound = |b: Option<&u32>| b.map(|&b| json::Value::from(vec![b]));
    root.push(json::Accessor {
        buffer_view: Some(view),
        byte_offset: Some(USize64(0)),
        count: USize64::from(tris.len()),
        component_type: Valid(GenericComponentType(ComponentType::U32)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(Type::Scalar),
        min: bound(tris.iter().min()),
        max: bound(tris.iter().max()),
        name: None,
        normalized: false,
        sparse: None,
    })
}

/// A GLB container (glTF 2.0 §4.4): the 12-byte header, the JSON chunk (padded with spaces)
/// and the BIN chunk (padded with zeros).
fn glb(mut json: Vec<u8>, mut bin: Vec<u8>, file: &str) -> Result<Vec<u8>, ExportError> {
    json.resize(json.len().next_multiple_of(4), b' ');
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let total = u32::try_from(total).map_err(|_| ExportError::Invalid {
        path: file.to_string(),
        what: format!("{total} bytes do not fit a GLB file (4 GiB at most)"),
    })?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    for (chunk, kind) in [(&json, b"JSON"), (&bin, b"BIN\0")] {
        out.extend_from_slice(&(chunk.len() as u32).to_le_bytes());
        out.extend_from_slice(kind);
        out.extend_from_slice(chunk);
    }
    Ok(out)
}
