//! Primvars of every interpolation and width from USD (indexed or not, merged over prims) and
//! vertex colours from OBJ, and typed errors for primvars that do not fit.

use subdiv_mesh::{Mesh, PrimvarInterpolation as I, UsdError, UsdReadOptions, parse_obj, read_usd};

fn stage(text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("subdiv-usd-primvars-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let n = text.len() ^ (text.bytes().map(u64::from).sum::<u64>() as usize);
    let path = dir.join(format!("stage-{n}.usda"));
    std::fs::write(&path, text).unwrap();
    path
}

const TWO_QUADS: &str = r#"#usda 1.0
def Mesh "A" {
    int[] faceVertexCounts = [4, 4]
    int[] faceVertexIndices = [0, 1, 4, 3, 1, 2, 5, 4]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0), (1, 1, 0), (2, 1, 0)]
    color3f[] primvars:displayColor = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (0, 1, 1), (1, 0, 1)] (
        interpolation = "vertex"
    )
    texCoord2f[] primvars:st1 = [(0, 0), (1, 0), (1, 1), (0, 1)] (
        interpolation = "faceVarying"
    )
    int[] primvars:st1:indices = [0, 1, 2, 3, 0, 1, 2, 3]
    float[] primvars:opacity = [0.25, 0.75] (
        interpolation = "uniform"
    )
    float[] primvars:weight = [0.5]
    float4[] primvars:extra = [(1, 2, 3, 4), (5, 6, 7, 8), (1, 1, 1, 1), (0, 0, 0, 0), (2, 2, 2, 2), (3, 3, 3, 3)] (
        interpolation = "varying"
    )
}
"#;

fn read(text: &str) -> Result<Mesh, UsdError> {
    read_usd(stage(text), &UsdReadOptions::default()).map(|c| c.mesh)
}

#[test]
fn every_interpolation_and_width_is_read() {
    let m = read(TWO_QUADS).unwrap();
    let names: Vec<&str> = m.primvars().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["displayColor", "st1", "opacity", "weight", "extra"]);
    let c = m.primvar("displayColor").unwrap();
    assert_eq!((c.interpolation, c.width), (I::Vertex, 3));
    assert_eq!(c.element(2), [0.0, 0.0, 1.0]);
    let st1 = m.primvar("st1").unwrap();
    assert_eq!((st1.interpolation, st1.width), (I::FaceVarying, 2));
    assert_eq!(st1.indices, [0, 1, 2, 3, 0, 1, 2, 3]);
    assert_eq!(st1.element(6), [1.0, 1.0]);
    let o = m.primvar("opacity").unwrap();
    assert_eq!(
        (o.interpolation, o.width, o.element(1)),
        (I::Uniform, 1, &[0.75][..])
    );
    let w = m.primvar("weight").unwrap();
    assert_eq!((w.interpolation, w.indices.len()), (I::Constant, 1));
    let e = m.primvar("extra").unwrap();
    assert_eq!((e.interpolation, e.width), (I::Varying, 4));
    assert_eq!(e.element(1), [5.0, 6.0, 7.0, 8.0]);
}

#[test]
fn merged_prims_append_their_values_and_constants_become_uniform() {
    let b = TWO_QUADS
        .replace("def Mesh \"A\"", "def Mesh \"B\"")
        .replace("[0.5]", "[2.5]")
        .replace("#usda 1.0\n", "");
    let m = read(&format!("{TWO_QUADS}{b}")).unwrap();
    let w = m.primvar("weight").unwrap();
    assert_eq!(w.interpolation, I::Uniform);
    assert_eq!(w.indices.len(), 4);
    assert_eq!((w.element(0), w.element(3)), (&[0.5][..], &[2.5][..]));
    let c = m.primvar("displayColor").unwrap();
    assert_eq!(c.indices.len(), 12);
    assert_eq!(c.element(8), [0.0, 0.0, 1.0]);
    let st1 = m.primvar("st1").unwrap();
    assert_eq!(st1.num_values(), 8);
    assert_eq!(st1.indices[8..], [4, 5, 6, 7, 4, 5, 6, 7]);
    // A primvar on one prim only.
    let b = b.replace("primvars:weight", "primvars:other");
    let e = read(&format!("{TWO_QUADS}{b}")).unwrap_err();
    assert!(
        matches!(
            e,
            UsdError::Mixed {
                attr: "primvars",
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn primvars_that_do_not_fit_are_typed_errors() {
    let short = TWO_QUADS.replace("[0.25, 0.75]", "[0.25]");
    let e = read(&short).unwrap_err().to_string();
    assert!(
        e.contains("/A: primvars:opacity: 1 values for 2 elements (uniform)"),
        "{e}"
    );
    let bad = TWO_QUADS.replace("[0, 1, 2, 3, 0, 1, 2, 3]", "[0, 1, 2, 3, 0, 1, 2, 9]");
    let e = read(&bad).unwrap_err().to_string();
    assert!(
        e.contains("primvars:st1:indices: index 7 is 9, outside the 4 values"),
        "{e}"
    );
    let token = TWO_QUADS.replace(
        "float[] primvars:weight = [0.5]",
        "token primvars:weight = \"heavy\"",
    );
    let e = read(&token).unwrap_err().to_string();
    assert!(e.contains("primvars:weight: expected float"), "{e}");
}

#[test]
fn obj_vertex_colours_are_the_display_colour() {
    let obj = "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\nf 1 2 3 4\n";
    let m = Mesh::from_soup(&parse_obj(obj).unwrap()).unwrap();
    let c = m.primvar("displayColor").unwrap();
    assert_eq!((c.interpolation, c.width), (I::Vertex, 3));
    assert_eq!(c.element(1), [0.0, 1.0, 0.0]);
    // A weight alone is not a colour; colours on some vertices only are an error.
    let w = parse_obj("v 0 0 0 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert!(w.primvars.is_empty());
    let e = parse_obj("v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0 0 1\nf 1 2 3\n").unwrap_err();
    assert!(e.to_string().contains("vertex 2 has no colour"), "{e}");
    assert_eq!(e.line(), Some(2));
}
