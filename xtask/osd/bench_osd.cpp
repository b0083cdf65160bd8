// bench_osd: times OpenSubdiv 3.5 (Far, CPU, float) on an OBJ cage with OpenSubdiv's tag lines.
//
//   bench_osd INPUT.obj DEPTH [RUNS] [catmark|loop]
//
// The scheme is Catmull-Clark unless the fourth argument is `loop` (then the cage must be all
// triangles).
//
// Two ways of getting the limit position and normal of every level-DEPTH vertex:
//
// cold     TopologyRefinerFactory<TopologyDescriptor>::Create from the cage, RefineUniform(DEPTH)
//          (full topology in the last level, as PrimvarRefiner::Limit needs), PrimvarRefiner::
//          Interpolate level by level, PrimvarRefiner::Limit(positions, du, dv), and the normal
//          normalize(du x dv). Everything from scratch every run.
// stencil  setup: Create + RefineAdaptive(isolation DEPTH) + LimitStencilTableFactory::Create at the
//          (ptex face, u, v) of every level-DEPTH vertex, each distinct point once (timed apart);
//          eval: UpdateValues + UpdateDerivs on the cage positions (positions + tangents), and
//          eval+n: the same plus normalize(du x dv).
//
// Each figure is the median of RUNS runs (after one warm-up run). The cage must be all quads for
// Catmull-Clark, all triangles for Loop (the stencil locations use ptex face = cage face). The last line is machine-readable:
//   osd points=<n> cold_pts_per_s=<f> stencil_setup_ms=<f> stencil_eval_pts_per_s=<f>
//   stencil_evaln_pts_per_s=<f>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "obj_cage.h"

using namespace OpenSubdiv;

struct Vec3 {
    float x, y, z;
    void Clear(void * = 0) { x = y = z = 0.0f; }
    void AddWithWeight(Vec3 const &s, float w) {
        x += w * s.x;
        y += w * s.y;
        z += w * s.z;
    }
};

// The cage as the benchmarks use it: float positions beside the parsed OBJ (`obj_cage.h`, the
// reader every harness shares). UVs are dropped: the timed refinement is of positions only.
struct Cage {
    std::vector<Vec3> positions;
    objcage::Cage obj;
    Sdc::SchemeType scheme = Sdc::SCHEME_CATMARK;
};

static void fail(std::string const &what) { objcage::fail("bench_osd", what); }

// OBJ with OpenSubdiv's tags (fixtures/reference/OSD_REFERENCE_FORMAT.md).
static Cage readObj(char const *path) {
    Cage c;
    c.obj = objcage::readObj(path, "bench_osd");
    if (!c.obj.holes.empty()) fail("hole tags are not supported by bench_osd");
    c.obj.uvs.clear();
    c.obj.faceUvs.clear();
    c.positions.resize(c.obj.numVertices());
    for (int v = 0; v < c.obj.numVertices(); ++v) {
        double const *p = &c.obj.positions[3 * v];
        c.positions[v] = Vec3{(float)p[0], (float)p[1], (float)p[2]};
    }
    return c;
}

static Far::TopologyRefiner *createRefiner(Cage const &c) {
    return objcage::createRefiner(c.obj, c.scheme, "bench_osd");
}

static inline Vec3 unitCross(Vec3 const &a, Vec3 const &b) {
    Vec3 n = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    float l = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (l > 0.0f) {
        n.x /= l;
        n.y /= l;
        n.z /= l;
    }
    return n;
}

// Cold: refine uniformly, interpolate, limit with tangents, normals. Returns the point count.
static size_t cold(Cage const &c, int depth, std::vector<Vec3> &pos, std::vector<Vec3> &nrm) {
    Far::TopologyRefiner *r = createRefiner(c);
    Far::TopologyRefiner::UniformOptions uo(depth);
    uo.fullTopologyInLastLevel = true;
    r->RefineUniform(uo);
    Far::PrimvarRefiner pr(*r);
    std::vector<Vec3> src(c.positions), dst;
    for (int level = 1; level <= depth; ++level) {
        dst.resize(r->GetLevel(level).GetNumVertices());
        Vec3 *s = src.data(), *d = dst.data();
        pr.Interpolate(level, s, d);
        src.swap(dst);
    }
    size_t n = src.size();
    pos.resize(n);
    nrm.resize(n);
    std::vector<Vec3> du(n), dv(n);
    Vec3 *s = src.data(), *p = pos.data(), *u = du.data(), *v = dv.data();
    pr.Limit(s, p, u, v);
    for (size_t i = 0; i < n; ++i) nrm[i] = unitCross(du[i], dv[i]);
    delete r;
    return n;
}

// Every level-depth vertex once: per quad face its interior grid, the inner points of the edges
// it is the first face of, and the cage vertices it is the first face of (u: v0->v1, v: v0->v3).
static void locations(Far::TopologyRefiner const &r, int depth, bool triangles,
                      std::vector<std::vector<float> > &us, std::vector<std::vector<float> > &vs) {
    Far::TopologyLevel const &base = r.GetLevel(0);
    int R = 1 << depth;
    float inv = 1.0f / (float)R;
    us.assign(base.GetNumFaces(), std::vector<float>());
    vs.assign(base.GetNumFaces(), std::vector<float>());
    for (int f = 0; f < base.GetNumFaces(); ++f) {
        Far::ConstIndexArray fv = base.GetFaceVertices(f), fe = base.GetFaceEdges(f);
        if (triangles) {
            if (fv.size() != 3) fail("bench_osd loop needs an all-triangle cage");
            bool firstE[3], firstV[3];
            for (int k = 0; k < 3; ++k) {
                firstE[k] = base.GetEdgeFaces(fe[k])[0] == f;
                firstV[k] = base.GetVertexFaces(fv[k])[0] == f;
            }
            // Loop's ptex triangle: corner 0 at (0, 0), 1 at (1, 0), 2 at (0, 1).
            for (int j = 0; j <= R; ++j) {
                for (int i = 0; i + j <= R; ++i) {
                    bool keep;
                    if (i == 0 && j == 0) keep = firstV[0];
                    else if (i == R) keep = firstV[1];
                    else if (j == R) keep = firstV[2];
                    else if (j == 0) keep = firstE[0];
                    else if (i + j == R) keep = firstE[1];
                    else if (i == 0) keep = firstE[2];
                    else keep = true;
                    if (keep) {
                        us[f].push_back(i * inv);
                        vs[f].push_back(j * inv);
                    }
                }
            }
            continue;
        }
        if (fv.size() != 4) fail("bench_osd needs an all-quad cage");
        bool firstE[4], firstV[4];
        for (int k = 0; k < 4; ++k) {
            firstE[k] = base.GetEdgeFaces(fe[k])[0] == f;
            firstV[k] = base.GetVertexFaces(fv[k])[0] == f;
        }
        for (int j = 0; j <= R; ++j) {
            for (int i = 0; i <= R; ++i) {
                bool bi = i == 0 || i == R, bj = j == 0 || j == R, keep;
                if (!bi && !bj) keep = true;
                else if (bi && bj) keep = firstV[i == 0 ? (j == 0 ? 0 : 3) : (j == 0 ? 1 : 2)];
                else if (bj) keep = firstE[j == 0 ? 0 : 2];
                else keep = firstE[i == R ? 1 : 3];
                if (keep) {
                    us[f].push_back(i * inv);
                    vs[f].push_back(j * inv);
                }
            }
        }
    }
}

typedef std::chrono::steady_clock Clock;
static double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
static double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// bench_animate.cpp includes this file for its cage reader and stencil locations.
#ifndef BENCH_OSD_NO_MAIN
int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: bench_osd INPUT.obj DEPTH [RUNS] [catmark|loop]\n");
        return 2;
    }
    Cage c = readObj(argv[1]);
    int depth = std::atoi(argv[2]);
    int runs = argc > 3 ? std::atoi(argv[3]) : 7;
    if (argc > 4 && std::string(argv[4]) == "loop") c.scheme = Sdc::SCHEME_LOOP;
    if (depth < 1 || depth > 10 || runs < 1) fail("DEPTH must be 1..10 and RUNS >= 1");

    std::vector<Vec3> pos, nrm;
    size_t points = cold(c, depth, pos, nrm);  // warm-up
    std::vector<double> tc;
    for (int k = 0; k < runs; ++k) {
        Clock::time_point t = Clock::now();
        cold(c, depth, pos, nrm);
        tc.push_back(since(t));
    }

    std::vector<std::vector<float> > us, vs;
    Far::LimitStencilTable const *table = 0;
    std::vector<double> ts;
    for (int k = 0; k <= runs; ++k) {
        delete table;
        Clock::time_point t = Clock::now();
        Far::TopologyRefiner *r = createRefiner(c);
        r->RefineAdaptive(Far::TopologyRefiner::AdaptiveOptions(depth));
        locations(*r, depth, c.scheme == Sdc::SCHEME_LOOP, us, vs);
        Far::LimitStencilTableFactory::LocationArrayVec locs(us.size());
        for (size_t f = 0; f < us.size(); ++f) {
            locs[f].ptexIdx = (int)f;
            locs[f].numLocations = (int)us[f].size();
            locs[f].s = us[f].data();
            locs[f].t = vs[f].data();
        }
        table = Far::LimitStencilTableFactory::Create(*r, locs);
        delete r;
        if (k > 0) ts.push_back(since(t));
    }
    size_t n = (size_t)table->GetNumStencils();
    if (n != points) {
        std::fprintf(stderr, "bench_osd: %zu stencil locations but %zu level-%d vertices\n", n, points, depth);
        return 1;
    }
    std::vector<Vec3> spos(n), du(n), dv(n), snrm(n);
    std::vector<double> te, ten;
    Vec3 const *cv = c.positions.data();
    Vec3 *sp = spos.data(), *u = du.data(), *v = dv.data();
    for (int k = 0; k <= runs; ++k) {
        Clock::time_point t = Clock::now();
        table->UpdateValues(cv, sp);
        table->UpdateDerivs(cv, u, v);
        double e = since(t);
        for (size_t i = 0; i < n; ++i) snrm[i] = unitCross(du[i], dv[i]);
        if (k > 0) {
            te.push_back(e);
            ten.push_back(since(t));
        }
    }
    // Same point set as the uniform path (order-independent sums).
    double a[3] = {0, 0, 0}, b[3] = {0, 0, 0}, scale = 1.0;
    for (size_t i = 0; i < n; ++i) {
        a[0] += pos[i].x, a[1] += pos[i].y, a[2] += pos[i].z;
        b[0] += spos[i].x, b[1] += spos[i].y, b[2] += spos[i].z;
        scale = std::max(scale, std::fabs((double)pos[i].x) + std::fabs((double)pos[i].y) + std::fabs((double)pos[i].z));
    }
    double err = std::max(std::fabs(a[0] - b[0]), std::max(std::fabs(a[1] - b[1]), std::fabs(a[2] - b[2]))) / (scale * n);
    if (err > 1e-4) {
        std::fprintf(stderr, "bench_osd: stencil points differ from the uniform limit points (%g)\n", err);
        return 1;
    }
    delete table;
    if (std::getenv("BENCH_OSD_SUMS")) {
        double q = 0.0;
        for (size_t i = 0; i < n; ++i) q += pos[i].x * pos[i].x + pos[i].y * pos[i].y + pos[i].z * pos[i].z;
        std::printf("sums %.9g %.9g %.9g %.9g\n", a[0], a[1], a[2], q);
    }

    double cm = median(tc), sm = median(ts), em = median(te), enm = median(ten);
    std::printf("input=%s depth=%d points=%zu runs=%d cold_ms=%.3f stencil_setup_ms=%.3f stencil_eval_ms=%.3f "
                "stencil_evaln_ms=%.3f\n",
                argv[1], depth, points, runs, cm * 1e3, sm * 1e3, em * 1e3, enm * 1e3);
    std::printf("osd points=%zu cold_pts_per_s=%.0f stencil_setup_ms=%.3f stencil_eval_pts_per_s=%.0f "
                "stencil_evaln_pts_per_s=%.0f\n",
                points, points / cm, sm * 1e3, points / em, points / enm);
    return 0;
}
#endif
