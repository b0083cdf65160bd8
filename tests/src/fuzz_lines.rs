//! Input fuzzing, part 3: single lines from the OBJ grammar, valid and invalid: OpenSubdiv `t`
//! tags (right and wrong argument counts, bad numbers, negative/NaN/inf sharpness, unknown
//! tags) and free sequences of `v`/`f`/`g`/... lines.

use std::fmt::Write as _;

use crate::fuzz::{Cage, Rng};

/// A sharpness as written: mostly sensible, sometimes negative, NaN, inf, huge or not a number.
fn sharpness(rng: &mut Rng) -> String {
    const ODD: &[&str] = &[
        "-1", "nan", "inf", "-inf", "1e39", "1e30", "-0", "x", "", "1e-45", "10", "0",
    ];
    if rng.chance(88) {
        format!("{}", rng.below(40) as f32 / 4.0)
    } else {
        rng.pick(ODD).to_string()
    }
}

/// A vertex index for a tag: usually a vertex of the cage, sometimes out of range.
fn tag_vertex(rng: &mut Rng, nv: usize) -> i64 {
    if rng.chance(85) && nv > 0 {
        rng.below(nv) as i64
    } else {
        *rng.pick(&[-1, nv as i64, nv as i64 + 7, i64::MAX, i64::MIN])
    }
}

/// A chain of vertices along one face of the cage (a real crease edge path), or random ones.
fn chain(rng: &mut Rng, cage: &Cage) -> Vec<i64> {
    let len = 2 + rng.below(3);
    if !cage.faces.is_empty() && rng.chance(80) {
        let f = &cage.faces[rng.below(cage.faces.len())];
        if !f.is_empty() {
            let s = rng.below(f.len());
            return (0..len.min(f.len() + 1))
                .map(|k| f[(s + k) % f.len()])
                .collect();
        }
    }
    (0..len).map(|_| tag_vertex(rng, cage.pos.len())).collect()
}

/// One `t` line.
pub fn tag_line(rng: &mut Rng, cage: &Cage) -> String {
    let nv = cage.pos.len();
    match rng.below(14) {
        0..=3 => {
            let vs = chain(rng, cage);
            let ns = match rng.below(4) {
                0 => vs.len().saturating_sub(1),
                1 => rng.below(4),
                _ => 1,
            };
            tag(
                "crease",
                &vs,
                &(0..ns).map(|_| sharpness(rng)).collect::<Vec<_>>(),
                &[],
                rng,
            )
        }
        4..=6 => {
            let vs: Vec<i64> = (0..1 + rng.below(3)).map(|_| tag_vertex(rng, nv)).collect();
            let ns = if rng.chance(50) { 1 } else { vs.len() };
            tag(
                "corner",
                &vs,
                &(0..ns).map(|_| sharpness(rng)).collect::<Vec<_>>(),
                &[],
                rng,
            )
        }
        7 | 8 => {
            let nf = cage.faces.len();
            let fs: Vec<i64> = (0..1 + rng.below(2))
                .map(|_| {
                    if rng.chance(85) && nf > 0 {
                        rng.below(nf) as i64
                    } else {
                        *rng.pick(&[-1, nf as i64, i64::MAX])
                    }
                })
                .collect();
            tag("hole", &fs, &[], &[], rng)
        }
        9 | 10 => {
            let k = if rng.chance(90) {
                rng.range(0, 2)
            } else {
                rng.range(-1, 3)
            };
            tag("interpolateboundary", &[k], &[], &[], rng)
        }
        11 => {
            let m = *rng.pick(&["chaikin", "uniform", "normal", "smooth", "CHAIKIN"]);
            tag("creasemethod", &[], &[], &[m], rng)
        }
        12 => {
            let name = *rng.pick(&[
                "facevaryinginterpolateboundary",
                "vertexedit",
                "smoothtriangles",
                "propagatecorners",
                "",
            ]);
            tag(name, &[1], &["1.0".into()], &[], rng)
        }
        _ => odd_tag(rng, cage),
    }
}

/// `t name ni/nf/ns ints floats strings`, with the counts occasionally wrong.
fn tag(name: &str, ints: &[i64], floats: &[String], strs: &[&str], rng: &mut Rng) -> String {
    let (mut ni, mut nf, mut ns) = (ints.len(), floats.len(), strs.len());
    if rng.chance(8) {
        match rng.below(3) {
            0 => ni += 1,
            1 => nf = nf.saturating_sub(1),
            _ => ns += 1,
        }
    }
    let mut s = format!("t {name} {ni}/{nf}/{ns}");
    for i in ints {
        let _ = write!(s, " {i}");
    }
    for f in floats {
        let _ = write!(s, " {f}");
    }
    for t in strs {
        let _ = write!(s, " {t}");
    }
    s
}

/// Tags whose counts field is malformed or overflows.
fn odd_tag(rng: &mut Rng, cage: &Cage) -> String {
    const COUNTS: &[&str] = &[
        "2/1",
        "2/1/0/0",
        "a/1/0",
        "-1/0/0",
        "//",
        "",
        "18446744073709551615/1/0",
        "18446744073709551615/18446744073709551615/2",
        "9223372036854775808/9223372036854775808/0",
        "99999999999999999999/0/0",
        "1/18446744073709551615/1",
        "2/1/0",
        "0/0/0",
    ];
    let name = *rng.pick(&[
        "crease",
        "corner",
        "hole",
        "interpolateboundary",
        "creasemethod",
        "x",
    ]);
    let mut s = format!("t {name} {}", rng.pick(COUNTS));
    for _ in 0..rng.below(4) {
        let _ = write!(s, " {}", tag_vertex(rng, cage.pos.len()));
    }
    if rng.chance(30) {
        s = "t".into();
    }
    s
}

/// A free sequence of grammar lines, indices drawn around the vertices read so far.
pub fn free_lines(rng: &mut Rng) -> String {
    let mut s = String::new();
    let mut nv = 0i64;
    for _ in 0..rng.below(30) {
        match rng.below(8) {
            0..=2 => {
                let _ = writeln!(s, "v {} {} {}", rng.unit(), rng.unit(), rng.unit());
                nv += 1;
            }
            3 | 4 => {
                s.push('f');
                for _ in 0..rng.below(6) {
                    let i = rng.range(-nv - 2, nv + 2);
                    let _ = write!(s, " {i}");
                    if rng.chance(10) {
                        s.push_str(rng.pick::<&str>(&["/1", "//1", "/1/1", "/", "//", "/x"]));
                    }
                }
                s.push('\n');
            }
            5 => {
                let cage = Cage {
                    pos: vec![[0.0; 3]; nv as usize],
                    faces: Vec::new(),
                };
                s.push_str(&tag_line(rng, &cage));
                s.push('\n');
            }
            6 => s.push_str(rng.pick::<&str>(&[
                "g a\n",
                "o b\n",
                "s 1\n",
                "vt 0 0\n",
                "vn 0 0 1\n",
                "#\n",
                "\n",
            ])),
            _ => s.push_str(rng.pick::<&str>(&[
                "v\n",
                "v 1\n",
                "f\n",
                "f x\n",
                "f 1 2 3x\n",
                "t\n",
                "v 1 2 3 4 5\n",
                "f 99999999999999999999\n",
                "f -9223372036854775808 1 2\n",
            ])),
        }
    }
    s
}
