//! Tests of the OBJ reader and writer (`obj.rs`).

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
        colours: None,
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
        colours: None,
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
        colours: None,
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
