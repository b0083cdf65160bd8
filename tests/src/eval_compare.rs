//! Exact evaluation (`subdiv-eval`) against OpenSubdiv 3.5's `Bfr::Surface` (`xtask/osd/
//! ref_eval.cpp`): the points both evaluate, the harness's output lines, the comparison and
//! its tolerances, and the truth where they differ (deep refinement of the point's vertex).

use glam::{DVec2, DVec3};
use subdiv::eval::{Derivatives, Domain, Evaluator, Query, Sample, random_queries, refined_faces};
use subdiv_mesh::{FaceId, Mesh};
use subdiv_rules::{Ring, Scheme, refine_uniform_levels_f64};

/// Positions agree within this times the cage's bounding-box diagonal.
pub const POSITION_TOL: f64 = 1e-5;
/// First derivatives' directions agree within this many degrees where the surface is regular.
pub const DIRECTION_DEG: f64 = 0.05;
/// UVs agree within this (absolute).
pub const UV_TOL: f64 = 1e-5;
/// Denominator of the dyadic points ([`bfr_points`]): they are vertices of the level-3 mesh.
pub const DYADIC_LEVEL: u8 = 3;

/// One point as `ref_eval` evaluates it: `None` for a hole.
#[derive(Clone, Debug, PartialEq)]
pub struct BfrValue {
    /// Position, du, dv, duu, duv, dvv.
    pub d: [DVec3; 6],
    /// UV, its du and dv, when the cage has UVs.
    pub uv: Option<[DVec2; 3]>,
    /// `Surface::IsRegular`: the face is one regular patch (no approximation).
    pub regular: bool,
}

/// Parses one `ref_eval` output line.
pub fn parse_bfr(line: &str) -> Result<Option<BfrValue>, String> {
    let t: Vec<&str> = line.split_whitespace().collect();
    if t == ["hole"] {
        return Ok(None);
    }
    let num = |i: usize| -> Result<f64, String> {
        t.get(i)
            .ok_or_else(|| format!("short line '{line}'"))?
            .parse()
            .map_err(|_| format!("bad number in '{line}'"))
    };
    let key = |i: usize, k: &str| -> Result<(), String> {
        (t.get(i) == Some(&k))
            .then_some(())
            .ok_or_else(|| format!("expected '{k}' in '{line}'"))
    };
    let mut d = [DVec3::ZERO; 6];
    for (k, name) in ["p", "du", "dv", "duu", "duv", "dvv"].iter().enumerate() {
        key(4 * k, name)?;
        d[k] = DVec3::new(num(4 * k + 1)?, num(4 * k + 2)?, num(4 * k + 3)?);
    }
    let mut i = 24;
    let uv = if t.get(i) == Some(&"uv") {
        let mut v = [DVec2::ZERO; 3];
        for (k, name) in ["uv", "uvdu", "uvdv"].iter().enumerate() {
            key(i, name)?;
            v[k] = DVec2::new(num(i + 1)?, num(i + 2)?);
            i += 3;
        }
        Some(v)
    } else {
        None
    };
    key(i, "regular")?;
    Ok(Some(BfrValue {
        d,
        uv,
        regular: num(i + 1)? == 1.0,
    }))
}

/// The corners of the level-[`DYADIC_LEVEL`] lattice cell around each of `queries` (its
/// vertices in the query's face, every combination of rounding `u` and `v` down and up),
/// without repeats: where a random point finds a difference near a feature, one of them is
/// nearer to it than the point's snapped one of [`bfr_points`] may be.
pub fn lattice_cell_corners(eval: &Evaluator<'_>, queries: &[Query]) -> Vec<Query> {
    let m = f64::from(1u32 << DYADIC_LEVEL);
    let mut out: Vec<Query> = Vec::new();
    for p in queries {
        let Ok(domain) = eval.domain(p.face) else {
            continue;
        };
        for u in [(p.u * m).floor() / m, (p.u * m).ceil() / m] {
            for v in [(p.v * m).floor() / m, (p.v * m).ceil() / m] {
                let q = Query::new(p.face, u, v);
                if domain.locate(u, v).is_some() && !out.contains(&q) {
                    out.push(q);
                }
            }
        }
    }
    out
}

/// The points a comparison draws: `n` uniform ones ([`random_queries`] from `seed`), then each
/// of them snapped to the nearest vertex of the level-[`DYADIC_LEVEL`] mesh in its face (where
/// [`DeepLimits`] is the truth: wherever the random points find a difference, a dyadic point
/// nearby can say which side is the limit surface).
pub fn bfr_points(eval: &Evaluator<'_>, n: usize, seed: u64) -> Vec<Query> {
    let mut q = random_queries(eval, n, seed);
    let m = f64::from(1u32 << DYADIC_LEVEL);
    let snapped: Vec<Query> = q
        .iter()
        .filter_map(|p| {
            let domain = eval.domain(p.face).ok()?;
            let snap = |x: f64| (x * m).round() / m;
            let (u, v) = (snap(p.u), snap(p.v));
            domain.locate(u, v).map(|_| Query::new(p.face, u, v))
        })
        .collect();
    q.extend(snapped);
    q
}

/// The limit surface at the dyadic points of a cage's level-[`DYADIC_LEVEL`] mesh, from deep
/// refinement: a point's vertex ring at that level refined 64 more times about its own centre,
/// whose centre then is the limit to rounding (refinement converges at every vertex, whatever
/// its limit masks say).
pub struct DeepLimits {
    refined: Mesh,
    pos: Vec<DVec3>,
    /// `(cage face, u, v)` bits of every level-3 face corner, and its vertex.
    at: std::collections::HashMap<(u32, u64, u64), subdiv_mesh::VertexId>,
    scheme: Scheme,
}

impl DeepLimits {
    /// The level-[`DYADIC_LEVEL`] mesh of `mesh`.
    pub fn new(mesh: &Mesh, scheme: Scheme) -> Option<DeepLimits> {
        let (refined, pos) = refine_uniform_levels_f64(mesh, scheme, DYADIC_LEVEL).ok()?;
        let mut at = std::collections::HashMap::new();
        for (f, (face, params)) in refined_faces(mesh, scheme, DYADIC_LEVEL).iter().enumerate() {
            let verts = refined.face_vertices(FaceId(f as u32));
            for (k, p) in params.iter().enumerate() {
                at.insert((*face, p[0].to_bits(), p[1].to_bits()), verts[k]);
            }
        }
        Some(DeepLimits {
            refined,
            pos,
            at,
            scheme,
        })
    }

    /// The limit at `q`, `None` off the level-[`DYADIC_LEVEL`] lattice.
    pub fn at(&self, q: Query) -> Option<DVec3> {
        let v = *self.at.get(&(q.face, q.u.to_bits(), q.v.to_bits()))?;
        let origin = self.pos[v.idx()];
        let mut ring = Ring::new();
        ring.load_at(
            &self.refined,
            |w| self.pos[w.idx()] - origin,
            v,
            self.scheme,
        );
        for _ in 0..64 {
            ring.refine();
        }
        Some(ring.center() + origin)
    }
}

/// Bfr's distance to deep refinement (x diagonal) at a dyadic point that shows Bfr is not the
/// limit surface of a cage: a thousand times subdiv's there.
pub const EXPLAINED: f64 = 1e-6;

/// Bfr's largest distance to deep refinement (x diagonal) at the dyadic points of `queries`
/// where subdiv is the deep refinement (within 1e-9 x diagonal), with its point.
pub fn bfr_off_limit(
    mesh: &Mesh,
    scheme: Scheme,
    queries: &[Query],
    values: &[Option<BfrValue>],
) -> (f64, String) {
    let (Some(deep), Ok(eval)) = (DeepLimits::new(mesh, scheme), Evaluator::new(mesh, scheme))
    else {
        return (0.0, String::new());
    };
    let (lo, hi) = mesh.bounds();
    let diag = f64::from((hi - lo).length()).max(f64::MIN_POSITIVE);
    let mut worst = (0.0, String::new());
    for (q, b) in queries.iter().zip(values) {
        let (Some(b), Some(truth)) = (b, deep.at(*q)) else {
            continue;
        };
        let Ok(s) = eval.evaluate(*q, Derivatives::First) else {
            continue;
        };
        let mine = (s.position - truth).length() / diag;
        let theirs = (b.d[0] - truth).length() / diag;
        if mine <= 1e-9 && theirs > worst.0 {
            worst = (theirs, format!("face {} ({}, {})", q.face, q.u, q.v));
        }
    }
    worst
}

/// Compares subdiv with Bfr's `values` at `queries` ([`Agreement::measure`]): `Ok(None)`
/// within the tolerances, `Ok(Some(why))` where Bfr is shown off the limit surface at a dyadic
/// point ([`bfr_off_limit`] beyond [`EXPLAINED`]), `Err` for a disagreement.
pub fn agree_or_explain(
    mesh: &Mesh,
    scheme: Scheme,
    queries: &[Query],
    values: &[Option<BfrValue>],
) -> Result<Option<String>, String> {
    let a = Agreement::measure(mesh, scheme, queries, values)?;
    let uvs = values.iter().flatten().any(|v| v.uv.is_some());
    match a.check(uvs) {
        Ok(()) => Ok(None),
        Err(e) => {
            let (off, at) = bfr_off_limit(mesh, scheme, queries, values);
            if off > EXPLAINED {
                Ok(Some(format!(
                    "{e}; Bfr {off:.2e} x diagonal from deep refinement at {at}"
                )))
            } else {
                Err(format!("{e} (Bfr {off:.2e} from deep refinement at {at})"))
            }
        }
    }
}

/// How subdiv and Bfr agree over a set of points.
#[derive(Clone, Debug, Default)]
pub struct Agreement {
    /// Points compared (holes excluded).
    pub points: usize,
    /// Largest position difference / diagonal.
    pub position: f64,
    /// Largest first-derivative direction difference (degrees) where Bfr's face is regular.
    pub direction_regular: f64,
    /// The same over all points but the face corners (where the parameterisation is singular).
    pub direction: f64,
    /// Largest relative second-derivative difference where Bfr's face is regular.
    pub second_regular: f64,
    /// Largest UV difference.
    pub uv: f64,
    /// Worst point of each measure, for messages.
    pub worst: [String; 4],
}

fn angle(a: DVec3, b: DVec3) -> f64 {
    if a.length_squared() == 0.0 || b.length_squared() == 0.0 {
        return 0.0;
    }
    a.angle_between(b).to_degrees()
}

impl Agreement {
    /// Compares subdiv's evaluation of `queries` with Bfr's `values` (`None`: a hole, which
    /// subdiv must refuse too).
    pub fn measure(
        mesh: &Mesh,
        scheme: Scheme,
        queries: &[Query],
        values: &[Option<BfrValue>],
    ) -> Result<Agreement, String> {
        let eval = Evaluator::new(mesh, scheme).map_err(|e| e.to_string())?;
        let (lo, hi) = mesh.bounds();
        let diag = f64::from((hi - lo).length()).max(f64::MIN_POSITIVE);
        let mut a = Agreement::default();
        let worse = |slot: usize, value: f64, best: &mut f64, what: String, a: &mut [String; 4]| {
            if value > *best {
                *best = value;
                a[slot] = what;
            }
        };
        for (q, b) in queries.iter().zip(values) {
            let Some(b) = b else {
                if eval.locate(*q).is_ok() {
                    return Err(format!("face {} is a hole for Bfr, not for subdiv", q.face));
                }
                continue;
            };
            let s: Sample = eval
                .evaluate(*q, Derivatives::Second)
                .map_err(|e| format!("face {} ({}, {}): {e}", q.face, q.u, q.v))?;
            a.points += 1;
            let at = format!("face {} ({}, {})", q.face, q.u, q.v);
            let dp = (s.position - b.d[0]).length() / diag;
            worse(
                0,
                dp,
                &mut a.position,
                format!("{at}: {} vs {}", s.position, b.d[0]),
                &mut a.worst,
            );
            let corner = is_corner(&eval.domain(q.face).map_err(|e| e.to_string())?, q);
            let dir = angle(s.du, b.d[1]).max(angle(s.dv, b.d[2]));
            if !corner {
                worse(
                    1,
                    dir,
                    &mut a.direction,
                    format!("{at}: du {} vs {}, dv {} vs {}", s.du, b.d[1], s.dv, b.d[2]),
                    &mut a.worst,
                );
            }
            if b.regular {
                a.direction_regular = a.direction_regular.max(dir);
                let scale = b.d[3]
                    .length()
                    .max(b.d[4].length())
                    .max(b.d[5].length())
                    .max(diag);
                let d2 = [(s.duu, b.d[3]), (s.duv, b.d[4]), (s.dvv, b.d[5])]
                    .iter()
                    .map(|(x, y)| (*x - *y).length() / scale)
                    .fold(0.0, f64::max);
                worse(
                    2,
                    d2,
                    &mut a.second_regular,
                    format!("{at}: second derivatives"),
                    &mut a.worst,
                );
            }
            if let (Some(buv), Some(suv)) = (b.uv, eval.evaluate_uv(*q).map_err(|e| e.to_string())?)
            {
                let duv = (suv.uv - buv[0]).length();
                worse(
                    3,
                    duv,
                    &mut a.uv,
                    format!("{at}: uv {} vs {}", suv.uv, buv[0]),
                    &mut a.worst,
                );
            }
        }
        Ok(a)
    }

    /// Fails beyond the tolerances: positions ([`POSITION_TOL`]), first-derivative directions
    /// where Bfr's face is regular ([`DIRECTION_DEG`]), UVs ([`UV_TOL`]) when `uvs`.
    pub fn check(&self, uvs: bool) -> Result<(), String> {
        if self.position > POSITION_TOL {
            return Err(format!(
                "position off by {:.3e} x diagonal at {}",
                self.position, self.worst[0]
            ));
        }
        if self.direction_regular > DIRECTION_DEG {
            return Err(format!(
                "derivative direction off by {:.4} deg on a regular face",
                self.direction_regular
            ));
        }
        if uvs && self.uv > UV_TOL {
            return Err(format!("UV off by {:.3e} at {}", self.uv, self.worst[3]));
        }
        Ok(())
    }
}

/// Whether `q` is a corner of its face (or of a sub-face).
fn is_corner(domain: &Domain, q: &Query) -> bool {
    let Some((_, s, t)) = domain.locate(q.u, q.v) else {
        return false;
    };
    (s == 0.0 || s == 1.0) && (t == 0.0 || t == 1.0)
        || (domain == &Domain::Triangle && (s, t) == (0.0, 1.0))
}

/// The fixture cages the Bfr references cover (paths relative to `fixtures/`) and the scheme
/// each is read with: from its OpenSubdiv reference's header where it has one, else `loop`
/// for a `loop_`/`tri_` name or a `scheme loop` comment, else Catmull-Clark.
pub fn eval_fixtures(fixtures: &std::path::Path) -> Vec<(String, Scheme)> {
    let dirs = [
        "reference/shapes",
        "meshes",
        "meshes/fvar",
        "nonmanifold",
        "osd_fuzz",
        "boundary_none",
        "osd_watertight",
        "loop_slate",
    ];
    let mut out = Vec::new();
    for dir in dirs {
        let Ok(entries) = std::fs::read_dir(fixtures.join(dir)) else {
            continue;
        };
        let mut files: Vec<_> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "obj"))
            .collect();
        files.sort();
        for path in files {
            let name = path
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .to_string();
            let stem = name.trim_end_matches(".obj");
            let header = ["L1", "L2", "L3", "L4"]
                .iter()
                .find_map(|l| {
                    std::fs::read_to_string(path.with_file_name(format!("{stem}.{l}.txt"))).ok()
                })
                .and_then(|t| t.lines().next().map(str::to_string));
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            let scheme = match header {
                Some(h) if h.contains("scheme=loop") => Scheme::Loop,
                Some(h) if h.contains("scheme=catmark") => Scheme::CatmullClark,
                _ if stem.starts_with("loop")
                    || stem.starts_with("tri_")
                    || text.contains("scheme loop") =>
                {
                    Scheme::Loop
                }
                _ => Scheme::CatmullClark,
            };
            out.push((format!("{dir}/{name}"), scheme));
        }
    }
    out
}

/// The name of a fixture's reference file in `fixtures/reference/eval/`.
pub fn eval_reference_name(rel: &str) -> String {
    rel.trim_end_matches(".obj").replace('/', "__") + ".txt"
}

/// `text` with every `v` and `vt` coordinate rounded to `f32` as subdiv reads it, so that
/// OpenSubdiv (reading `f64`) evaluates the same cage.
pub fn obj_rounded_to_f32(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let mut it = line.split_whitespace();
        let kw = it.next();
        if matches!(kw, Some("v" | "vt")) {
            let nums: Option<Vec<f32>> = it.map(|x| x.parse::<f32>().ok()).collect();
            if let Some(nums) = nums {
                out.push_str(kw.unwrap_or_default());
                for x in nums {
                    out.push_str(&format!(" {x}"));
                }
                out.push('\n');
                continue;
            }
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}
