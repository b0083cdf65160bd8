//! Input fuzzing, part 1: a deterministic generator of OBJ inputs. No dependency: a SplitMix64
//! stream drives a grammar of valid and invalid OBJ lines, a set of topologies (manifold,
//! non-manifold, mis-oriented, huge valence, degenerate) and byte-level mutations, so every case
//! is reproducible from `(seed, index)`. The checker is in [`crate::fuzz_check`].

use std::fmt::Write as _;

/// The random stream of the fuzzers and generators: [`Rng::for_case`] (SplitMix64).
pub use subdiv_test_support::Rng;

/// One generated input: the bytes and what produced them (for the report).
#[derive(Clone, Debug)]
pub struct Input {
    /// The file content.
    pub bytes: Vec<u8>,
    /// How it was made: `raw`, `mutated` or the topology family.
    pub kind: &'static str,
}

/// The input of one case: 10% raw bytes, 20% mutated structured text, 70% structured text.
pub fn input(rng: &mut Rng) -> Input {
    match rng.below(10) {
        0 => Input {
            bytes: raw_bytes(rng),
            kind: "raw",
        },
        1 | 2 => {
            let (text, _) = structured(rng);
            Input {
                bytes: mutate(rng, text.into_bytes()),
                kind: "mutated",
            }
        }
        _ => {
            let (text, kind) = structured(rng);
            Input {
                bytes: text.into_bytes(),
                kind,
            }
        }
    }
}

/// Bytes drawn from an OBJ-ish alphabet, or any bytes at all.
fn raw_bytes(rng: &mut Rng) -> Vec<u8> {
    const ALPHA: &[u8] = b"vftgos/ -+.0123456789eEnaif#\n\n\t\rx";
    let n = rng.below(300);
    let any = rng.chance(30);
    (0..n)
        .map(|_| {
            if any {
                rng.next_u64() as u8
            } else {
                *rng.pick(ALPHA)
            }
        })
        .collect()
}

/// A few byte-level edits of OBJ text (see [`mutate_with`]).
fn mutate(rng: &mut Rng, b: Vec<u8>) -> Vec<u8> {
    mutate_with(rng, b, b"vft0123456789-/ .\n#e+naif\x00\xff")
}

/// One to six byte-level edits: flip a bit, insert a byte of `alphabet`, delete, truncate,
/// duplicate a span elsewhere.
pub fn mutate_with(rng: &mut Rng, mut b: Vec<u8>, alphabet: &[u8]) -> Vec<u8> {
    const INS: &[u8] = b"\x00";
    let ins = if alphabet.is_empty() { INS } else { alphabet };
    for _ in 0..1 + rng.below(6) {
        if b.is_empty() {
            b.push(*rng.pick(ins));
            continue;
        }
        let i = rng.below(b.len());
        match rng.below(5) {
            0 => b[i] ^= 1 << rng.below(8),
            1 => b.insert(i, *rng.pick(ins)),
            2 => {
                b.remove(i);
            }
            3 => b.truncate(i),
            _ => {
                let j = (i + 1 + rng.below(40)).min(b.len());
                let span: Vec<u8> = b[i..j].to_vec();
                let at = rng.below(b.len());
                b.splice(at..at, span);
            }
        }
    }
    b
}

/// A cage before it is written: positions and 0-based faces (possibly invalid).
#[derive(Clone, Debug, Default)]
pub struct Cage {
    /// Positions.
    pub pos: Vec<[f32; 3]>,
    /// Faces, 0-based; may hold out-of-range, repeated or too few indices.
    pub faces: Vec<Vec<i64>>,
}

/// Structured OBJ text: a topology, mutated, written with decorations and tags; or a free
/// sequence of grammar lines. Returns the text and the family name.
fn structured(rng: &mut Rng) -> (String, &'static str) {
    if rng.chance(15) {
        return (crate::fuzz_lines::free_lines(rng), "lines");
    }
    let (mut cage, kind) = crate::fuzz_topo::topology(rng);
    crate::fuzz_topo::mutate_cage(rng, &mut cage);
    (write_cage(rng, &cage), kind)
}

/// Writes a cage as OBJ with random index forms, junk statements, line endings and tags.
fn write_cage(rng: &mut Rng, cage: &Cage) -> String {
    let mut s = String::new();
    let crlf = rng.chance(10);
    let nl = if crlf { "\r\n" } else { "\n" };
    let faces_first = rng.chance(3);
    if faces_first {
        write_faces(rng, cage, &mut s, nl);
    }
    let broken = rng.chance(20);
    for p in &cage.pos {
        junk(rng, &mut s, nl, 10);
        let _ = write!(s, "v {}", vertex_coords(rng, p, broken));
        s.push_str(nl);
    }
    if !faces_first {
        write_faces(rng, cage, &mut s, nl);
    }
    let ntags = if rng.chance(50) { rng.below(6) } else { 0 };
    for _ in 0..ntags {
        s.push_str(&crate::fuzz_lines::tag_line(rng, cage));
        s.push_str(nl);
    }
    junk(rng, &mut s, nl, 20);
    if rng.chance(10) {
        s.truncate(s.trim_end().len());
    }
    s
}

fn write_faces(rng: &mut Rng, cage: &Cage, s: &mut String, nl: &str) {
    let nv = cage.pos.len() as i64;
    let form = rng.below(6);
    for f in &cage.faces {
        junk(rng, s, nl, 8);
        s.push('f');
        for &i in f {
            let _ = write!(s, " {}", face_index(rng, i, nv, form));
        }
        if rng.chance(3) {
            s.push_str(" # trailing comment");
        }
        s.push_str(nl);
    }
}

/// A 0-based index in one of OBJ's forms (`i`, `i/t`, `i//n`, `i/t/n`, negative), per file or
/// mixed per index (`form == 5`).
fn face_index(rng: &mut Rng, i: i64, nv: i64, form: usize) -> String {
    let form = if form == 5 { rng.below(5) } else { form };
    let obj = if form == 4 && i < nv { i - nv } else { i + 1 };
    match form {
        1 => format!("{obj}/{}", 1 + rng.below(4)),
        2 => format!("{obj}//{}", 1 + rng.below(4)),
        3 => format!("{obj}/{}/{}", 1 + rng.below(4), 1 + rng.below(4)),
        _ => format!("{obj}"),
    }
}

/// The coordinates of a `v` line, sometimes broken: missing, extra, non-numeric, NaN, inf,
/// out of `f32` range (in a `broken` file, one line in ten).
fn vertex_coords(rng: &mut Rng, p: &[f32; 3], broken: bool) -> String {
    if !broken || !rng.chance(10) {
        return format!("{} {} {}", p[0], p[1], p[2]);
    }
    const BAD: &[&str] = &[
        "nan",
        "NaN",
        "inf",
        "-inf",
        "1e39",
        "-1e39",
        "1e-50",
        "x",
        "0x10",
        "1,5",
        "--1",
        "1e",
        ".",
        "+",
        "infinity",
        "3.4028235e38",
    ];
    match rng.below(4) {
        0 => format!("{} {}", p[0], p[1]),
        1 => format!("{} {} {} 1.0", p[0], p[1], p[2]),
        2 => String::new(),
        _ => {
            let k = rng.below(3);
            let c: Vec<String> = (0..3)
                .map(|j| {
                    if j == k {
                        rng.pick(BAD).to_string()
                    } else {
                        p[j].to_string()
                    }
                })
                .collect();
            c.join(" ")
        }
    }
}

/// With probability `percent`, a statement the reader must skip or group by.
fn junk(rng: &mut Rng, s: &mut String, nl: &str, percent: u64) {
    if !rng.chance(percent) {
        return;
    }
    const LINES: &[&str] = &[
        "# comment",
        "",
        "   ",
        "\t",
        "vt 0.5 0.5",
        "vn 0 0 1",
        "vp 0.1",
        "g",
        "g group one",
        "o object",
        "s 1",
        "s off",
        "usemtl red",
        "mtllib a.mtl",
        "l 1 2",
        "p 1",
        "#t crease 2/1/0 0 1 1",
        "vx 1 2 3",
    ];
    s.push_str(rng.pick::<&str>(LINES));
    s.push_str(nl);
}

/// The environment variable `name` as a number (decimal, or hex after `0x`), or `default`
/// when it is unset; a value that is not a number fails the test that asked, naming it.
pub fn env_u64(name: &str, default: u64) -> u64 {
    match std::env::var(name) {
        Ok(s) => {
            let s = s.trim();
            let v = match s.strip_prefix("0x") {
                Some(h) => u64::from_str_radix(h, 16),
                None => s.parse(),
            };
            v.unwrap_or_else(|_| panic!("{name}={s}: not a number"))
        }
        Err(_) => default,
    }
}
