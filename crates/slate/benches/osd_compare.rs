//! Slate tessellator vs `opensubdiv-rs` (a Rust port of OpenSubdiv's Far), in one process, on the
//! same cages (catmark_pawn, catmark_helmet, cc_3torus) at uniform depths 2..=5.
//!
//! Run: `cargo bench -p subdiv-slate --bench osd_compare` (criterion prints the per-benchmark
//! times; a table of limit points per second and the ratios goes to stderr at the end).
//! `SUBDIV_OSD_COMPARE_QUICK=1` restricts the run to depth 2..=3 (a smoke run).
//!
//! What each side does per timed iteration (all single-threaded unless the name says `2t`):
//!
//! - `slate_1t` / `slate_2t`: `tessellate_layout_into(&mesh, &layout, &mut out)` inside a rayon
//!   pool of 1 / 2 threads, timed on a thread of that pool (as a renderer thread of the pool would
//!   call it; entering the pool from outside costs a thread hand-off per call, not timed). The [`PatchLayout`] is built once before timing and `out` is reused
//!   (the per-frame steady state); each iteration computes every limit position and unit limit
//!   normal of the depth-N tessellation plus its quad index buffer. No setup is timed.
//! - `osdrs_limit_stencils` (the headline `opensubdiv-rs` figure, positions + normals, cold):
//!   `TopologyRefinerFactory::create` from the cage (faces, crease and corner tags, boundary
//!   interpolation and creasing method from the OBJ tags), `refine_adaptive` with isolation level N,
//!   `LimitStencilTableFactory::create` at the (ptex face, u, v) location of every level-N vertex
//!   (each distinct point once), `update_values` + `update_derivs` on the cage positions, and the
//!   normal `normalize(du x dv)` per point. The port's `PrimvarRefiner::limit` has no tangent
//!   output, so the limit stencils are the only way it offers to get limit normals. Only the
//!   location list (pure topology bookkeeping, independent of the positions) is precomputed.
//! - `osdrs_refine_limit_pos` (context, positions only, cold): `TopologyRefinerFactory::create`,
//!   `refine_uniform(N)`, `PrimvarRefiner::interpolate` level by level and `PrimvarRefiner::limit`
//!   on level N. No normals: this side does strictly less work than the slates.
//!
//! Throughput is counted in distinct level-N limit points (the slate output's vertex count, equal
//! to the port's level-N vertex count and to the number of stencil locations; both are checked).
//! Where the three point sets differ (order-independent sums of x, y, z, |p|^2), a note is printed.
//!
//! Every cage here is all-quads, which keeps ptex faces = cage faces for the location list.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput};
use opensubdiv_rs::far::{
    AdaptiveOptions, LimitStencilTableFactory, LocationArray, PrimvarRefiner, TopologyDescriptor,
    TopologyRefiner, TopologyRefinerFactory, UniformOptions,
};
use opensubdiv_rs::sdc;
use subdiv_mesh::{BoundaryInterpolation, CreaseMethod, PolygonSoup};
use subdiv_slate::{
    PatchLayout, slate_bytes_per_thread, tessellate_layout, tessellate_layout_into,
};

const CAGES: &[(&str, &str)] = &[
    ("catmark_pawn", "fixtures/reference/shapes/catmark_pawn.obj"),
    (
        "catmark_helmet",
        "fixtures/reference/shapes/catmark_helmet.obj",
    ),
    ("cc_3torus", "fixtures/meshes/cc_3torus.obj"),
];

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The cage as the port wants it: a polygon soup with crease/corner tags and scheme options.
struct OsdCage {
    num_vertices: usize,
    positions: Vec<[f32; 3]>,
    verts_per_face: Vec<usize>,
    face_verts: Vec<u32>,
    crease_pairs: Vec<[u32; 2]>,
    crease_weights: Vec<f32>,
    corners: Vec<u32>,
    corner_weights: Vec<f32>,
    options: sdc::Options,
}

impl OsdCage {
    fn from_soup(soup: &PolygonSoup) -> OsdCage {
        let idx = |i: i64| u32::try_from(i).expect("validated cage index");
        let verts_per_face = soup
            .face_offsets
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
            .collect();
        let boundary = match soup.options.boundary {
            BoundaryInterpolation::None => sdc::VtxBoundaryInterpolation::None,
            BoundaryInterpolation::EdgeOnly => sdc::VtxBoundaryInterpolation::EdgeOnly,
            BoundaryInterpolation::EdgeAndCorner => sdc::VtxBoundaryInterpolation::EdgeAndCorner,
        };
        let creasing = match soup.options.crease {
            CreaseMethod::Uniform => sdc::CreasingMethod::Uniform,
            CreaseMethod::Chaikin => sdc::CreasingMethod::Chaikin,
        };
        OsdCage {
            num_vertices: soup.positions.len(),
            positions: soup.positions.iter().map(|p| p.to_array()).collect(),
            verts_per_face,
            face_verts: soup.face_indices.iter().map(|&i| idx(i)).collect(),
            crease_pairs: soup.creases.iter().map(|c| [idx(c.a), idx(c.b)]).collect(),
            crease_weights: soup.creases.iter().map(|c| c.sharpness).collect(),
            corners: soup.corners.iter().map(|c| idx(c.v)).collect(),
            corner_weights: soup.corners.iter().map(|c| c.sharpness).collect(),
            options: sdc::Options::default()
                .with_vtx_boundary_interpolation(boundary)
                .with_creasing_method(creasing),
        }
    }

    fn refiner(&self) -> TopologyRefiner {
        let desc =
            TopologyDescriptor::new(self.num_vertices, &self.verts_per_face, &self.face_verts)
                .with_creases(&self.crease_pairs, &self.crease_weights)
                .with_corners(&self.corners, &self.corner_weights);
        TopologyRefinerFactory::create(desc, sdc::SchemeType::Catmark, self.options)
            .expect("fixture cage is a valid OpenSubdiv topology")
    }
}

/// One (u, v) list per ptex face (= cage face: all-quad cages) holding every level-`depth` vertex
/// exactly once: a face's interior grid points, the inner points of the edges it is the first
/// face of, and the cage vertices it is the first face of. Quad ptex frame: u along v0->v1,
/// v along v0->v3.
fn level_locations(refiner: &TopologyRefiner, depth: u32) -> Vec<(Vec<f32>, Vec<f32>)> {
    let base = refiner.level(0);
    let r = 1usize << depth;
    let inv = 1.0 / r as f32;
    (0..base.num_faces())
        .map(|f| {
            let fv = base.face_vertices(f);
            let fe = base.face_edges(f);
            assert_eq!(fv.len(), 4, "osd_compare needs all-quad cages");
            let first_of_edge = |k: usize| base.edge_faces(fe[k] as usize)[0] as usize == f;
            let first_of_vertex = |k: usize| base.vertex_faces(fv[k] as usize)[0] as usize == f;
            let (mut us, mut vs) = (Vec::new(), Vec::new());
            for j in 0..=r {
                for i in 0..=r {
                    let (bi, bj) = (i == 0 || i == r, j == 0 || j == r);
                    let keep = match (bi, bj) {
                        (false, false) => true,
                        (true, true) => first_of_vertex(match (i == 0, j == 0) {
                            (true, true) => 0,
                            (false, true) => 1,
                            (false, false) => 2,
                            (true, false) => 3,
                        }),
                        (false, true) => first_of_edge(if j == 0 { 0 } else { 2 }),
                        (true, false) => first_of_edge(if i == r { 1 } else { 3 }),
                    };
                    if keep {
                        us.push(i as f32 * inv);
                        vs.push(j as f32 * inv);
                    }
                }
            }
            (us, vs)
        })
        .collect()
}

/// `opensubdiv-rs` cold: refine adaptively, limit stencils at every level-N vertex, positions +
/// derivatives, normals. Returns the number of points.
fn osdrs_limit_stencils(
    cage: &OsdCage,
    depth: u32,
    locs: &[(Vec<f32>, Vec<f32>)],
    pos: &mut Vec<[f32; 3]>,
    nrm: &mut Vec<[f32; 3]>,
) -> usize {
    let mut refiner = cage.refiner();
    refiner.refine_adaptive(AdaptiveOptions::new(depth as usize));
    let arrays: Vec<LocationArray<'_>> = locs
        .iter()
        .enumerate()
        .map(|(f, (u, v))| LocationArray::new(f as u32, u, v))
        .collect();
    let table = LimitStencilTableFactory::create(&refiner, &arrays, None, None)
        .expect("every location lies on the limit surface");
    let n = table.num_stencils();
    pos.resize(n, [0.0; 3]);
    nrm.resize(n, [0.0; 3]);
    let mut du = vec![[0.0f32; 3]; n];
    let mut dv = vec![[0.0f32; 3]; n];
    table.update_values(&cage.positions, pos);
    table.update_derivs(&cage.positions, &mut du, &mut dv);
    for ((nv, a), b) in nrm.iter_mut().zip(&du).zip(&dv) {
        let c = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        *nv = if l > 0.0 {
            [c[0] / l, c[1] / l, c[2] / l]
        } else {
            [0.0; 3]
        };
    }
    n
}

/// `opensubdiv-rs` cold: uniform refinement, interpolation level by level, limit positions.
fn osdrs_refine_limit_pos(cage: &OsdCage, depth: u32, pos: &mut Vec<[f32; 3]>) -> usize {
    let mut refiner = cage.refiner();
    refiner.refine_uniform(UniformOptions::new(depth as usize));
    let primvar = PrimvarRefiner::new(&refiner);
    let mut src = cage.positions.clone();
    for level in 1..=depth as usize {
        let mut dst = vec![[0.0f32; 3]; refiner.level(level).num_vertices()];
        primvar.interpolate(level, &src, &mut dst);
        src = dst;
    }
    pos.resize(src.len(), [0.0; 3]);
    primvar.limit(&src, pos);
    src.len()
}

fn sums(points: &[[f32; 3]]) -> [f64; 4] {
    let mut s = [0.0f64; 4];
    for p in points {
        for k in 0..3 {
            s[k] += f64::from(p[k]);
        }
        s[3] += p.iter().map(|&x| f64::from(x) * f64::from(x)).sum::<f64>();
    }
    s
}

/// Per-iteration times (seconds) of every benchmark, keyed by (cage, depth, side).
type Samples = Mutex<BTreeMap<(String, u32, String), Vec<f64>>>;

fn timed(
    samples: &Samples,
    key: (String, u32, String),
    iters: u64,
    mut f: impl FnMut(),
) -> Duration {
    let t = Instant::now();
    for _ in 0..iters {
        f();
    }
    let d = t.elapsed();
    samples
        .lock()
        .unwrap()
        .entry(key)
        .or_default()
        .push(d.as_secs_f64() / iters as f64);
    d
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let mut c = Criterion::default().configure_from_args().sample_size(10);
    let quick = std::env::var_os("SUBDIV_OSD_COMPARE_QUICK").is_some();
    let depths: &[u32] = if quick { &[2, 3] } else { &[2, 3, 4, 5] };
    let pool1 = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let pool2 = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let samples: Samples = Mutex::new(BTreeMap::new());
    let mut info = BTreeMap::new();

    for &(name, rel) in CAGES {
        let path = workspace_root().join(rel);
        let mesh =
            subdiv_mesh::read_obj(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let soup =
            subdiv_mesh::read_obj_soup(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let cage = OsdCage::from_soup(&soup);
        for &depth in depths {
            let layout = PatchLayout::new(&mesh, depth as subdiv_slate::Depth)
                .expect("fixture cage tessellates");
            let mut out = tessellate_layout(&mesh, &layout).expect("fixture cage tessellates");
            let points = out.positions().len();

            // Same point set on both sides (count and order-independent sums).
            let mut refiner = cage.refiner();
            refiner.refine_uniform(UniformOptions::new(depth as usize));
            assert_eq!(
                refiner.level(depth as usize).num_vertices(),
                points,
                "{name} depth {depth}"
            );
            let locs = level_locations(&refiner, depth);
            let (mut pos, mut nrm) = (Vec::new(), Vec::new());
            assert_eq!(
                osdrs_limit_stencils(&cage, depth, &locs, &mut pos, &mut nrm),
                points
            );
            let mut upos = Vec::new();
            osdrs_refine_limit_pos(&cage, depth, &mut upos);
            let (a, b, u) = (sums(out.positions()), sums(&pos), sums(&upos));
            let rel = |x: [f64; 4]| {
                (0..4).map(|k| (a[k] - x[k]).abs()).fold(0.0, f64::max) / a[3].max(1.0)
            };
            if rel(b).max(rel(u)) > 1e-6 {
                eprintln!(
                    "osd_compare: note: {name} depth {depth}: point sets differ (sum x, y, z, |p|^2): \
                     slate {a:?}, opensubdiv-rs uniform limit {u:?}, opensubdiv-rs limit stencils {b:?}"
                );
            }
            info.insert(
                (name.to_string(), depth),
                (
                    points,
                    layout.num_patches(),
                    slate_bytes_per_thread(depth as subdiv_slate::Depth, layout.max_valence()),
                ),
            );

            let mut g = c.benchmark_group(format!("osd_compare/{name}"));
            g.throughput(Throughput::Elements(points as u64));
            g.sample_size(10);
            g.warm_up_time(Duration::from_millis(500));
            g.measurement_time(Duration::from_secs(if depth >= 5 { 4 } else { 2 }));
            let key = |side: &str| (name.to_string(), depth, side.to_string());
            for (side, pool) in [("slate_1t", &pool1), ("slate_2t", &pool2)] {
                g.bench_function(BenchmarkId::new(side, depth), |bch| {
                    bch.iter_custom(|iters| {
                        // Timed inside the pool: the hand-off from this thread into the pool
                        // (a wake-up and a sleep per call) is not the tessellator's work.
                        pool.install(|| {
                            timed(&samples, key(side), iters, || {
                                tessellate_layout_into(&mesh, &layout, &mut out).unwrap();
                                std::hint::black_box(&out);
                            })
                        })
                    })
                });
            }
            g.bench_function(BenchmarkId::new("osdrs_limit_stencils", depth), |bch| {
                bch.iter_custom(|iters| {
                    timed(&samples, key("osdrs_limit_stencils"), iters, || {
                        osdrs_limit_stencils(&cage, depth, &locs, &mut pos, &mut nrm);
                        std::hint::black_box((&pos, &nrm));
                    })
                })
            });
            g.bench_function(BenchmarkId::new("osdrs_refine_limit_pos", depth), |bch| {
                bch.iter_custom(|iters| {
                    timed(&samples, key("osdrs_refine_limit_pos"), iters, || {
                        osdrs_refine_limit_pos(&cage, depth, &mut pos);
                        std::hint::black_box(&pos);
                    })
                })
            });
            g.finish();
        }
    }
    c.final_summary();

    let samples = samples.into_inner().unwrap();
    let rate = |name: &str, depth: u32, side: &str, points: usize| {
        samples
            .get(&(name.to_string(), depth, side.to_string()))
            .map_or(f64::NAN, |s| points as f64 / median(s))
    };
    eprintln!();
    eprintln!("osd_compare: limit points per second (medians of criterion samples, M = 1e6)");
    eprintln!(
        "{:<15} {:>2} {:>8} {:>7} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>8} {:>7}",
        "cage",
        "N",
        "points",
        "patches",
        "slate_1t",
        "slate_2t",
        "2t/1t",
        "osdrs_st",
        "1t/osdrs",
        "rs_pos",
        "1t/rspos",
        "slateB"
    );
    for ((name, depth), (points, patches, bytes)) in &info {
        let s1 = rate(name, *depth, "slate_1t", *points);
        let s2 = rate(name, *depth, "slate_2t", *points);
        let st = rate(name, *depth, "osdrs_limit_stencils", *points);
        let rp = rate(name, *depth, "osdrs_refine_limit_pos", *points);
        eprintln!(
            "{:<15} {:>2} {:>8} {:>7} {:>8.2}M {:>8.2}M {:>8.2}x {:>8.3}M {:>8.0}x {:>8.3}M {:>7.0}x {:>7}",
            name,
            depth,
            points,
            patches,
            s1 / 1e6,
            s2 / 1e6,
            s2 / s1,
            st / 1e6,
            s1 / st,
            rp / 1e6,
            s1 / rp,
            bytes
        );
    }
}
