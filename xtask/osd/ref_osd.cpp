// ref_osd: reference limit surfaces from OpenSubdiv 3.5 (Far, CPU, double precision) in the format
// of fixtures/reference/OSD_REFERENCE_FORMAT.md.
//
//   ref_osd INPUT.obj LEVEL [catmark|loop|bilinear [local]]  > shape.L<LEVEL>.txt
//
// Reads an OBJ cage with OpenSubdiv's tag lines (crease, corner, hole, interpolateboundary,
// creasemethod, and smoothtriangles as OpenSubdiv's regression/common/far_utils.h spells it:
// `t smoothtriangles 0/0/1 smooth|catmark`), refines it uniformly to LEVEL with
// TopologyRefiner::RefineUniform, interpolates with PrimvarRefinerReal<double>, and prints every
// level-LEVEL vertex's limit position and normal (PrimvarRefiner::Limit with both tangents,
// normal = normalize(du x dv)) and the level-LEVEL faces (hole faces left out).
//
// With semi-sharp creases the limit is taken M levels deeper (M = LEVEL + ceil(max sharpness)),
// from the vertex's descendant, so it is the true limit rather than OpenSubdiv's shortcut of
// treating leftover sharpness as infinite; the header then says exact_from_level=M.
//
// `local` (used by `cargo xtask fuzz-osd`) takes each vertex's limit instead at the first level
// L in LEVEL..M where the vertex's descendant has no semi-sharp sharpness left on itself or its
// edges (its rule is final there); the header adds exact=per-vertex. For most vertices that is
// the same point, since OpenSubdiv's limit masks are exact once the rule is final. Not for darts
// and interior valence-2 vertices: OpenSubdiv gives them the smooth and the corner masks, which
// are not their true limit, so their "limit" moves with the level it is taken at. subdiv takes
// it, as here, at the level where the vertex's own neighbourhood has run out.
//
// Build: g++ -O2 -std=c++14 ref_osd.cpp -I/usr/include -losdCPU -o ref_osd (with obj_cage.h beside it)

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include "obj_cage.h"
#include <opensubdiv/version.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

struct Vec3 {
    double x, y, z;
    void Clear(void * = 0) { x = y = z = 0.0; }
    void AddWithWeight(Vec3 const &s, double w) {
        x += w * s.x;
        y += w * s.y;
        z += w * s.z;
    }
};

static char const *const TOOL = "ref_osd";

static void fail(std::string const &what) { objcage::fail(TOOL, what); }

static int semiSharpCount(std::vector<float> const &w, float *maxSharp) {
    int n = 0;
    for (float s : w) {
        if (s > 0.0f && s < 10.0f) {
            ++n;
            *maxSharp = std::max(*maxSharp, s);
        }
    }
    return n;
}

struct Limits {
    std::vector<Vec3> pos, du, dv;
};

// Refines `r` (already refined to its max level) uniformly in primvars and takes the limit of
// every vertex of its last level.
static Limits limitsAtMaxLevel(Far::TopologyRefiner const &r, std::vector<Vec3> const &cage) {
    int deep = r.GetMaxLevel();
    Far::PrimvarRefinerReal<double> pr(r);
    std::vector<std::vector<Vec3> > lv(deep + 1);
    lv[0] = cage;
    for (int l = 1; l <= deep; ++l) {
        lv[l].resize(r.GetLevel(l).GetNumVertices());
        Vec3 const *src = lv[l - 1].data();
        Vec3 *dst = lv[l].data();
        pr.Interpolate(l, src, dst);
    }
    size_t nd = lv[deep].size();
    Limits out;
    out.pos.resize(nd);
    out.du.resize(nd);
    out.dv.resize(nd);
    Vec3 const *src = lv[deep].data();
    Vec3 *p = out.pos.data(), *u = out.du.data(), *w = out.dv.data();
    pr.Limit(src, p, u, w);
    return out;
}

static bool semiSharp(float s) { return s > 0.0f && s < 10.0f; }

// No semi-sharp sharpness left on vertex v of level l or on its edges: its rule is final.
static bool settled(Far::TopologyLevel const &l, int v) {
    if (semiSharp(l.GetVertexSharpness(v))) return false;
    Far::ConstIndexArray es = l.GetVertexEdges(v);
    for (int k = 0; k < es.size(); ++k) {
        if (semiSharp(l.GetEdgeSharpness(es[k]))) return false;
    }
    return true;
}

int main(int argc, char **argv) {
    if (argc < 3) fail("usage: ref_osd INPUT.obj LEVEL [catmark|loop|bilinear [local]]");
    objcage::Cage c = objcage::readObj(argv[1], TOOL);
    std::vector<Vec3> cagePositions(c.numVertices());
    for (int v = 0; v < c.numVertices(); ++v) {
        cagePositions[v] = Vec3{c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]};
    }
    int level = std::atoi(argv[2]);
    std::string name = argc > 3 ? argv[3] : "catmark";
    bool loop = name == "loop", bilinear = name == "bilinear";
    if (!loop && !bilinear && name != "catmark") fail("scheme: catmark, loop or bilinear");
    bool local = argc > 4 && std::string(argv[4]) == "local";
    if (level < 1 || level > 8) fail("LEVEL must be 1..8");
    float maxSharp = 0.0f;
    int semiE = semiSharpCount(c.creaseWeights, &maxSharp);
    int semiV = semiSharpCount(c.cornerWeights, &maxSharp);
    // Sharpness does not move bilinear points: its limit is the level's own points.
    int deep = bilinear ? level : level + (int)std::ceil(maxSharp);
    Sdc::SchemeType scheme = loop ? Sdc::SCHEME_LOOP : bilinear ? Sdc::SCHEME_BILINEAR : Sdc::SCHEME_CATMARK;

    Far::TopologyRefiner *r = objcage::createRefiner(c, scheme, TOOL);
    Far::TopologyRefiner::UniformOptions uo(deep);
    uo.fullTopologyInLastLevel = true;
    r->RefineUniform(uo);
    // limits[l - level]: the limits at level l (local mode: every level from LEVEL to deep;
    // otherwise only deep).
    std::vector<Limits> limits(deep - level + 1);
    limits[deep - level] = limitsAtMaxLevel(*r, cagePositions);
    for (int l = level; local && l < deep; ++l) {
        Far::TopologyRefiner *rl = objcage::createRefiner(c, scheme, TOOL);
        Far::TopologyRefiner::UniformOptions ul(l);
        ul.fullTopologyInLastLevel = true;
        rl->RefineUniform(ul);
        limits[l - level] = limitsAtMaxLevel(*rl, cagePositions);
        delete rl;
    }

    Far::TopologyLevel const &L = r->GetLevel(level);
    int nv = L.GetNumVertices(), nf = 0;
    for (int f = 0; f < L.GetNumFaces(); ++f) nf += L.IsFaceHole(f) ? 0 : 1;
    Sdc::Options const &o = c.options;
    char const *bnd[] = {"none", "edge-only", "edge-and-corner"};
    std::printf("osdref %d %d scheme=%s level=%d mode=uniform-limit boundary=%s crease=%s tri=%s "
                "real=double holes=%d(omitted) semisharp_edges=%d semisharp_verts=%d "
                "limit_exact=yes limit_impl=osd base_verts=%d base_faces=%d osd=%s",
                nv, nf, name.c_str(), level, bnd[o.GetVtxBoundaryInterpolation()],
                o.GetCreasingMethod() == Sdc::Options::CREASE_CHAIKIN ? "chaikin" : "uniform",
                o.GetTriangleSubdivision() == Sdc::Options::TRI_SUB_SMOOTH ? "smooth" : "catmark",
                (int)c.holes.size(), semiE, semiV, c.numVertices(),
                (int)c.vertsPerFace.size(), "3.5.0");
    if (deep > level) std::printf(" exact_from_level=%d", deep);
    if (local) std::printf(" exact=per-vertex");
    std::printf("\n");
    for (int v = 0; v < nv; ++v) {
        // The vertex's descendant at the first level where its own rule is final (local), or
        // at `deep`.
        int d = v, l = level;
        for (; l < deep && !(local && settled(r->GetLevel(l), d)); ++l) {
            d = r->GetLevel(l).GetVertexChildVertex(d);
        }
        Limits const &lim = limits[l - level];
        std::vector<Vec3> const &pos = lim.pos;
        Vec3 const &a = lim.du[d], &b = lim.dv[d];
        double n[3] = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
        double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        // Parallel tangents (an interior valence-2 vertex whose two edges line up, seed 13 cage
        // 16024): du x dv is rounding noise (|du x dv| = 2e-14 |du| |dv| there, from 1e-16
        // components across the exact direction), and normalizing it gives an arbitrary
        // direction. The normal is undefined: print 0 0 0, as subdiv returns it.
        double la = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
        double lb = std::sqrt(b.x * b.x + b.y * b.y + b.z * b.z);
        if (len > 1e-12 * la * lb) {
            for (double &x : n) x /= len;
        } else {
            n[0] = n[1] = n[2] = 0.0;
        }
        std::printf("p %.9g %.9g %.9g %.9g %.9g %.9g\n", pos[d].x, pos[d].y, pos[d].z, n[0],
                    n[1], n[2]);
    }
    for (int f = 0; f < L.GetNumFaces(); ++f) {
        if (L.IsFaceHole(f)) continue;
        Far::ConstIndexArray fv = L.GetFaceVertices(f);
        std::printf("f");
        for (int k = 0; k < fv.size(); ++k) std::printf(" %d", fv[k]);
        std::printf("\n");
    }
    delete r;
    return 0;
}
