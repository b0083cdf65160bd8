//! USD input fuzzing, the generator: `.usda` stages built from a grammar of `UsdGeomMesh`
//! attributes (the topologies of [`crate::fuzz_topo`], with creases, corners, holes, schemes,
//! `primvars:st`, time samples, transforms, composition arcs and typed defects), the same text
//! byte-mutated, and byte-mutated binary `.usdc` crate files and `.usdz` archives. Binary seeds
//! are the fixtures `fixtures/usd/scene.usdc` and `open_lefthanded.usdz` (made by Pixar's USD
//! library) and grammar-built stages encoded by `openusd`'s own crate and archive writers.
//! Every case is reproducible from `(seed, index)`; the checker is
//! [`crate::fuzz_check::check_usd`].

use std::fmt::Write as _;
use std::io::Cursor;

use crate::fuzz::{Cage, Rng, mutate_with};

/// One generated USD file: its bytes, the extension it must be read with and how it was made.
#[derive(Clone, Debug)]
pub struct UsdInput {
    /// The file content.
    pub bytes: Vec<u8>,
    /// `usda`, `usdc` or `usdz`.
    pub ext: &'static str,
    /// How it was made (`grammar`, `usda-mutated`, `usdc-fixture-mutated`, ...).
    pub kind: &'static str,
}

/// The binary seeds from `fixtures/usd`, read once.
pub struct Seeds {
    /// `scene.usdc`: two meshes under transforms, an inactive mesh, a Scope.
    pub usdc: Vec<u8>,
    /// `open_lefthanded.usdz`: a left-handed open mesh in an archive.
    pub usdz: Vec<u8>,
}

impl Seeds {
    /// Reads the fixtures.
    pub fn load() -> Seeds {
        let dir = crate::fixtures().join("usd");
        let read = |n: &str| {
            std::fs::read(dir.join(n)).unwrap_or_else(|e| panic!("fixtures/usd/{n}: {e}"))
        };
        Seeds {
            usdc: read("scene.usdc"),
            usdz: read("open_lefthanded.usdz"),
        }
    }
}

/// The input of one case: 40% grammar-built `.usda`, 15% mutated `.usda`, 25% `.usdc` and 20%
/// `.usdz` (mostly mutated; a binary file is mutated unless it is a plain encoding of a
/// grammar-built stage, drawn 1 time in 5).
pub fn usd_input(rng: &mut Rng, seeds: &Seeds) -> UsdInput {
    let draw = rng.below(20);
    let (ext, kind, bytes) = match draw {
        0..=7 => ("usda", "grammar", stage_text(rng).into_bytes()),
        8..=10 => {
            let text = stage_text(rng).into_bytes();
            ("usda", "usda-mutated", mutate_text(rng, text))
        }
        11..=15 => {
            let (kind, b) = usdc_bytes(rng, seeds);
            ("usdc", kind, b)
        }
        _ => {
            let (kind, b) = usdz_bytes(rng, seeds);
            ("usdz", kind, b)
        }
    };
    UsdInput { bytes, ext, kind }
}

/// Byte edits of `.usda` text, inserting bytes of its grammar.
fn mutate_text(rng: &mut Rng, b: Vec<u8>) -> Vec<u8> {
    mutate_with(
        rng,
        b,
        b"()[]{}<>@\"'=,.:;-+0123456789e#\n \tabcdefsuint\x00\xff",
    )
}

/// Binary edits: the text edits plus whole little-endian integers overwritten with boundary
/// values (counts, offsets and indices of a crate file or a zip directory).
fn mutate_binary(rng: &mut Rng, mut b: Vec<u8>) -> Vec<u8> {
    const WIDE: &[u64] = &[
        0,
        1,
        0x7F,
        0x80,
        0xFF,
        0xFFFF,
        0x7FFF_FFFF,
        0x8000_0000,
        0xFFFF_FFFF,
        0x1_0000_0000,
        0x7FFF_FFFF_FFFF_FFFF,
        u64::MAX,
        u64::MAX - 7,
    ];
    for _ in 0..1 + rng.below(4) {
        if b.len() < 8 {
            break;
        }
        let at = rng.below(b.len() - 7);
        match rng.below(4) {
            0 => b[at..at + 8].copy_from_slice(&rng.pick(WIDE).to_le_bytes()),
            1 => b[at..at + 4].copy_from_slice(&(*rng.pick(WIDE) as u32).to_le_bytes()),
            2 => b[at] = rng.next_u64() as u8,
            _ => {
                // A small integer nudged: counts off by a few.
                let v = u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]);
                let d = rng.range(-3, 3) as i32;
                b[at..at + 4].copy_from_slice(&v.wrapping_add_signed(d).to_le_bytes());
            }
        }
    }
    if rng.chance(40) {
        b = mutate_with(rng, b, b"\x00\x01\x7f\x80\xff");
    }
    b
}

/// A grammar-built stage as `.usdc`, encoded by `openusd`'s crate writer (`None` when the text
/// does not parse, or the writer refuses it).
fn encode_usdc(text: &str) -> Option<Vec<u8>> {
    let data = openusd::usda::parse(text).ok()?;
    let mut out = Cursor::new(Vec::new());
    openusd::usdc::CrateWriter::write(&data, &mut out).ok()?;
    Some(out.into_inner())
}

/// `layer` (the archive's root layer, named `name`) in a `.usdz` archive, by `openusd`'s writer.
fn encode_usdz(name: &str, layer: &[u8]) -> Option<Vec<u8>> {
    let mut w = openusd::usdz::ArchiveWriter::new(Cursor::new(Vec::new()));
    w.add_layer(name, layer).ok()?;
    Some(w.finish().ok()?.into_inner())
}

/// A grammar stage parsed and written as a crate file; the fixture when that fails.
fn generated_usdc(rng: &mut Rng, seeds: &Seeds) -> (bool, Vec<u8>) {
    // Valid stages only: a stage with defects of its own text rarely parses.
    let text = valid_stage_text(rng);
    match encode_usdc(&text) {
        Some(b) => (true, b),
        None => (false, seeds.usdc.clone()),
    }
}

fn usdc_bytes(rng: &mut Rng, seeds: &Seeds) -> (&'static str, Vec<u8>) {
    match rng.below(5) {
        0 => {
            let (made, b) = generated_usdc(rng, seeds);
            (
                if made {
                    "usdc-generated"
                } else {
                    "usdc-fixture"
                },
                b,
            )
        }
        1 | 2 => {
            let (_, b) = generated_usdc(rng, seeds);
            ("usdc-generated-mutated", mutate_binary(rng, b))
        }
        _ => (
            "usdc-fixture-mutated",
            mutate_binary(rng, seeds.usdc.clone()),
        ),
    }
}

fn usdz_bytes(rng: &mut Rng, seeds: &Seeds) -> (&'static str, Vec<u8>) {
    match rng.below(5) {
        0 | 1 => {
            // An archive of a grammar stage, as text or as a crate file.
            let text = valid_stage_text(rng);
            let usdc = if rng.chance(50) {
                encode_usdc(&text)
            } else {
                None
            };
            let packed = match &usdc {
                Some(c) => encode_usdz("stage.usdc", c),
                None => encode_usdz("stage.usda", text.as_bytes()),
            };
            let b = packed.unwrap_or_else(|| seeds.usdz.clone());
            if rng.chance(20) {
                ("usdz-generated", b)
            } else {
                ("usdz-generated-mutated", mutate_binary(rng, b))
            }
        }
        _ => (
            "usdz-fixture-mutated",
            mutate_binary(rng, seeds.usdz.clone()),
        ),
    }
}

/// Options of the stage writer: whether defects are drawn at all.
#[derive(Clone, Copy)]
struct Style {
    /// Typed defects (wrong value types, bad tokens, broken arcs) are drawn.
    defects: bool,
}

/// A grammar-built stage (defects drawn).
pub fn stage_text(rng: &mut Rng) -> String {
    write_stage(rng, Style { defects: true })
}

/// A grammar-built stage without typed defects (its topology may still be invalid).
pub fn valid_stage_text(rng: &mut Rng) -> String {
    write_stage(rng, Style { defects: false })
}

fn write_stage(rng: &mut Rng, st: Style) -> String {
    let mut s = String::from("#usda 1.0\n(\n    defaultPrim = \"World\"\n");
    if rng.chance(30) {
        let up = if st.defects && rng.chance(10) {
            "\"Q\""
        } else {
            *rng.pick(&["\"Y\"", "\"Z\""])
        };
        let _ = writeln!(s, "    upAxis = {up}");
    }
    if st.defects && rng.chance(8) {
        // Sublayers that do not exist, or the stage itself (a cycle), or odd paths.
        let l = *rng.pick(&[
            "@missing.usda@",
            "@./case.usda@",
            "@@",
            "@/@",
            "@case.usda@, @case.usda@",
        ]);
        let _ = writeln!(s, "    subLayers = [{l}]");
    }
    if rng.chance(20) {
        let _ = writeln!(
            s,
            "    startTimeCode = {}\n    endTimeCode = {}",
            rng.range(-5, 5),
            rng.range(-5, 20)
        );
    }
    s.push_str(")\n\n");
    let nmesh = if rng.chance(80) { 1 } else { 2 + rng.below(2) };
    s.push_str("def Xform \"World\"\n{\n");
    if rng.chance(40) {
        xform_ops(rng, &mut s, "    ", st);
    }
    for k in 0..nmesh {
        let (mut cage, _) = crate::fuzz_topo::topology(rng);
        crate::fuzz_topo::mutate_cage(rng, &mut cage);
        let nested = rng.chance(30);
        let ind = if nested { "        " } else { "    " };
        if nested {
            let _ = writeln!(s, "    def Xform \"G{k}\"\n    {{");
            xform_ops(rng, &mut s, ind, st);
        }
        write_mesh(rng, &mut s, &cage, k, ind, st);
        if nested {
            s.push_str("    }\n");
        }
    }
    s.push_str("}\n");
    if st.defects && rng.chance(5) {
        // A second root prim referencing the first, or a missing file.
        let arc = *rng.pick(&[
            "</World>",
            "@missing.usda@",
            "@./case.usda@</World>",
            "</Nope>",
        ]);
        let _ = writeln!(s, "\ndef \"Ref\" (\n    references = {arc}\n)\n{{\n}}");
    }
    s
}

/// The `xformOp`s of a prim and their order (sometimes naming an op that is not authored,
/// sometimes singular or mirroring, sometimes time-sampled).
fn xform_ops(rng: &mut Rng, s: &mut String, ind: &str, st: Style) {
    let mut order = Vec::new();
    for _ in 0..1 + rng.below(3) {
        match rng.below(6) {
            0 => {
                let _ = writeln!(
                    s,
                    "{ind}double3 xformOp:translate = ({}, {}, {})",
                    rng.range(-5, 5),
                    rng.range(-5, 5),
                    rng.range(-5, 5)
                );
                order.push("xformOp:translate");
            }
            1 => {
                let _ = writeln!(
                    s,
                    "{ind}float3 xformOp:rotateXYZ = ({}, {}, {})",
                    rng.range(-180, 180),
                    rng.range(-180, 180),
                    rng.range(-180, 180)
                );
                order.push("xformOp:rotateXYZ");
            }
            2 => {
                let mut v = [0; 3].map(|_| *rng.pick(&[1.0f32, 1.0, 2.0, 0.5]));
                // Mirroring, singular and extreme scales.
                if rng.chance(30) {
                    v[rng.below(3)] = *rng.pick(&[-1.0, 0.0, 1e30, 1e-30, 3.0]);
                }
                let _ = writeln!(
                    s,
                    "{ind}float3 xformOp:scale = ({}, {}, {})",
                    v[0], v[1], v[2]
                );
                order.push("xformOp:scale");
            }
            3 => {
                let _ = writeln!(
                    s,
                    "{ind}float xformOp:rotateZ.timeSamples = {{\n{ind}    0: {},\n{ind}    1: {},\n{ind}}}",
                    rng.range(-90, 90),
                    rng.range(-90, 90)
                );
                order.push("xformOp:rotateZ");
            }
            4 => {
                let m: Vec<String> = (0..16)
                    .map(|i| {
                        if i % 5 == 0 {
                            "1".to_string()
                        } else if (12..15).contains(&i) {
                            rng.range(-3, 3).to_string()
                        } else if rng.chance(10) {
                            format!("{}", rng.unit())
                        } else {
                            "0".to_string()
                        }
                    })
                    .collect();
                let _ = writeln!(
                    s,
                    "{ind}matrix4d xformOp:transform = (({}), ({}), ({}), ({}))",
                    m[0..4].join(", "),
                    m[4..8].join(", "),
                    m[8..12].join(", "),
                    m[12..16].join(", ")
                );
                order.push("xformOp:transform");
            }
            _ => {
                if st.defects {
                    // Named in the order but never authored, or reset.
                    order.push(*rng.pick(&["xformOp:translate:missing", "!resetXformStack!"]));
                } else {
                    order.push("!resetXformStack!");
                    order.rotate_right(1);
                }
            }
        }
    }
    if st.defects && rng.chance(10) {
        order.reverse();
    }
    let quoted: Vec<String> = order.iter().map(|o| format!("\"{o}\"")).collect();
    let _ = writeln!(
        s,
        "{ind}uniform token[] xformOpOrder = [{}]",
        quoted.join(", ")
    );
}

/// An `int[]` literal.
fn ints(v: impl IntoIterator<Item = i64>) -> String {
    let v: Vec<String> = v.into_iter().map(|i| i.to_string()).collect();
    format!("[{}]", v.join(", "))
}

/// A `float` as USD text (`nan`, `inf` and `-inf` as USD writes them).
fn float(x: f32) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x == f32::INFINITY {
        "inf".into()
    } else if x == f32::NEG_INFINITY {
        "-inf".into()
    } else {
        format!("{x}")
    }
}

fn points(cage: &Cage) -> String {
    let v: Vec<String> = cage
        .pos
        .iter()
        .map(|p| format!("({}, {}, {})", float(p[0]), float(p[1]), float(p[2])))
        .collect();
    format!("[{}]", v.join(", "))
}

/// A sharpness: mostly semi-sharp up to 4 or infinitely sharp (10), sometimes negative, NaN,
/// infinite or huge. Semi-sharp values stay at or below 4 because the slate's UVs of a cage
/// with `primvars:st` refine the whole cage uniformly to the sharpness's level (exponential in
/// it: sharpness 9 on a large cage runs for minutes, see docs/testing.md), which is not what
/// this fuzzer is after.
fn sharpness(rng: &mut Rng) -> String {
    match rng.below(20) {
        0 | 1 => rng
            .pick(&["-1", "nan", "inf", "1e30", "-0", "1e-45"])
            .to_string(),
        2 => "10".to_string(),
        _ => format!("{}", rng.below(17) as f32 / 4.0),
    }
}

/// One `Mesh` prim.
fn write_mesh(rng: &mut Rng, s: &mut String, cage: &Cage, k: usize, ind: &str, st: Style) {
    let meta = if rng.chance(5) {
        "(\n    active = false\n)"
    } else if st.defects && rng.chance(3) {
        *rng.pick(&[
            "(\n    references = </World>\n)",
            "(\n    payload = @missing.usda@\n)",
            "(\n    kind = \"component\"\n)",
            "(\n    instanceable = true\n)",
        ])
    } else {
        ""
    };
    let _ = writeln!(s, "{ind}def Mesh \"M{k}\" {meta}\n{ind}{{");
    let a = format!("{ind}    ");
    let nv = cage.pos.len();
    let nf = cage.faces.len();
    // Topology: the cage's faces, sometimes typed wrongly or with odd counts.
    let counts = ints(cage.faces.iter().map(|f| f.len() as i64));
    let idx = ints(cage.faces.iter().flatten().copied());
    let counts = if st.defects && rng.chance(5) {
        rng.pick(&[
            "[]",
            "[-1]",
            "[2147483647]",
            "[4, -4]",
            "[0, 0]",
            "[9223372036854775807]",
        ])
        .to_string()
    } else {
        counts
    };
    let int_ty = if st.defects && rng.chance(4) {
        *rng.pick(&["float[]", "int64[]", "uint[]", "string[]", "int", "half[]"])
    } else {
        "int[]"
    };
    if !(st.defects && rng.chance(3)) {
        let _ = writeln!(s, "{a}{int_ty} faceVertexCounts = {counts}");
    }
    if !(st.defects && rng.chance(3)) {
        let _ = writeln!(s, "{a}int[] faceVertexIndices = {idx}");
    }
    // Points: a plain value, time samples (read at the earliest), or both.
    let pty = if st.defects && rng.chance(4) {
        *rng.pick(&[
            "point3d[]",
            "float3[]",
            "point3h[]",
            "float[]",
            "color3f[]",
            "point3f",
        ])
    } else {
        *rng.pick(&[
            "point3f[]",
            "point3f[]",
            "point3f[]",
            "float3[]",
            "point3d[]",
        ])
    };
    match rng.below(10) {
        0 | 1 => {
            let mut moved = cage.clone();
            for q in &mut moved.pos {
                q[2] += 1.0;
            }
            let t0 = rng.range(-3, 3);
            let _ = writeln!(
                s,
                "{a}{pty} points.timeSamples = {{\n{a}    {}: {},\n{a}    {t0}: {},\n{a}}}",
                t0 + 1 + rng.range(0, 2),
                points(&moved),
                points(cage)
            );
        }
        2 if st.defects => {}
        _ => {
            let _ = writeln!(s, "{a}{pty} points = {}", points(cage));
        }
    }
    // Creases along face edges (one sharpness per crease or per edge), sometimes mismatched.
    if rng.chance(35) && nf > 0 {
        let mut idx = Vec::new();
        let mut lengths = Vec::new();
        let mut sharp = Vec::new();
        let per_edge = rng.chance(40);
        for _ in 0..1 + rng.below(3) {
            let f = &cage.faces[rng.below(nf)];
            if f.is_empty() {
                continue;
            }
            let len = 2 + rng.below(f.len().min(4));
            let at = rng.below(f.len());
            idx.extend((0..len).map(|j| f[(at + j) % f.len()]));
            lengths.push(len as i64);
            let n = if per_edge { len - 1 } else { 1 };
            sharp.extend((0..n).map(|_| sharpness(rng)));
        }
        if st.defects && rng.chance(15) {
            match rng.below(3) {
                0 => lengths.push(rng.range(-2, 40)),
                1 => idx.push(*rng.pick(&[-1, nv as i64, i64::from(i32::MAX)])),
                _ => {
                    sharp.pop();
                }
            }
        }
        let _ = writeln!(s, "{a}int[] creaseIndices = {}", ints(idx));
        let _ = writeln!(s, "{a}int[] creaseLengths = {}", ints(lengths));
        let _ = writeln!(s, "{a}float[] creaseSharpnesses = [{}]", sharp.join(", "));
    }
    if rng.chance(25) && nv > 0 {
        let n = 1 + rng.below(3);
        let vs: Vec<i64> = (0..n)
            .map(|_| {
                if st.defects && rng.chance(10) {
                    *rng.pick(&[-1, nv as i64, i64::from(i32::MAX)])
                } else {
                    rng.below(nv) as i64
                }
            })
            .collect();
        let ns = if st.defects && rng.chance(10) {
            n + 1
        } else {
            n
        };
        let sh: Vec<String> = (0..ns).map(|_| sharpness(rng)).collect();
        let _ = writeln!(s, "{a}int[] cornerIndices = {}", ints(vs));
        let _ = writeln!(s, "{a}float[] cornerSharpnesses = [{}]", sh.join(", "));
    }
    if rng.chance(15) && nf > 0 {
        let hs: Vec<i64> = (0..1 + rng.below(2))
            .map(|_| {
                if st.defects && rng.chance(10) {
                    *rng.pick(&[-1, nf as i64])
                } else {
                    rng.below(nf) as i64
                }
            })
            .collect();
        let _ = writeln!(s, "{a}int[] holeIndices = {}", ints(hs));
    }
    tokens(rng, s, &a, st);
    if rng.chance(20) {
        texture_coordinates(rng, s, cage, &a, st);
    }
    if rng.chance(25) {
        xform_ops(rng, s, &a, st);
    }
    let _ = writeln!(s, "{ind}}}");
}

/// The uniform tokens: scheme, boundary, triangle rule, face-varying rule, orientation.
fn tokens(rng: &mut Rng, s: &mut String, a: &str, st: Style) {
    let attrs: [(&str, &[&str]); 5] = [
        (
            "subdivisionScheme",
            &["catmullClark", "loop", "bilinear", "none"],
        ),
        (
            "interpolateBoundary",
            &["none", "edgeOnly", "edgeAndCorner"],
        ),
        ("triangleSubdivisionRule", &["catmullClark", "smooth"]),
        (
            "faceVaryingLinearInterpolation",
            &[
                "none",
                "cornersOnly",
                "cornersPlus1",
                "cornersPlus2",
                "boundaries",
                "all",
            ],
        ),
        ("orientation", &["rightHanded", "leftHanded"]),
    ];
    for (name, values) in attrs {
        if !rng.chance(30) {
            continue;
        }
        if st.defects && rng.chance(8) {
            let bad = *rng.pick(&[
                "uniform token {n} = \"bogus\"",
                "uniform string {n} = \"loop\"",
                "uniform int {n} = 1",
                "uniform token[] {n} = [\"loop\"]",
                "uniform token {n} = \"\"",
            ]);
            let _ = writeln!(s, "{a}{}", bad.replace("{n}", name));
        } else {
            let _ = writeln!(s, "{a}uniform token {name} = \"{}\"", rng.pick(values));
        }
    }
}

/// `primvars:st`: face-varying (indexed or not), vertex, uniform or constant, with counts that
/// sometimes disagree with the faces.
fn texture_coordinates(rng: &mut Rng, s: &mut String, cage: &Cage, a: &str, st: Style) {
    let corners: usize = cage.faces.iter().map(Vec::len).sum();
    let interp = *rng.pick(&[
        "faceVarying",
        "faceVarying",
        "vertex",
        "uniform",
        "constant",
        "varying",
    ]);
    let indexed = interp == "faceVarying" && rng.chance(50);
    let n = match interp {
        "faceVarying" if indexed => 1 + rng.below(corners.max(1)),
        "faceVarying" => corners,
        "vertex" | "varying" => cage.pos.len(),
        "uniform" => cage.faces.len(),
        _ => 1,
    };
    let n = if st.defects && rng.chance(10) {
        (n + rng.below(3)).saturating_sub(1)
    } else {
        n
    };
    let uv: Vec<String> = (0..n)
        .map(|_| {
            if st.defects && rng.chance(2) {
                "(nan, 0)".to_string()
            } else {
                format!("({}, {})", rng.unit(), rng.unit())
            }
        })
        .collect();
    let ty = if st.defects && rng.chance(5) {
        *rng.pick(&["float3[]", "float[]", "double2[]", "texCoord2f"])
    } else {
        *rng.pick(&["texCoord2f[]", "float2[]", "texCoord2d[]"])
    };
    let _ = writeln!(
        s,
        "{a}{ty} primvars:st = [{}] (\n{a}    interpolation = \"{interp}\"\n{a})",
        uv.join(", ")
    );
    if indexed {
        let idx = (0..corners).map(|_| {
            if st.defects && rng.chance(2) {
                *rng.pick(&[-1, n as i64])
            } else {
                rng.below(n) as i64
            }
        });
        let _ = writeln!(s, "{a}int[] primvars:st:indices = {}", ints(idx));
    }
}
