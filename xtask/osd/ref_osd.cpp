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
// Build: g++ -O2 -std=c++14 ref_osd.cpp -I/usr/include -losdCPU -o ref_osd

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
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

struct Cage {
    std::vector<Vec3> positions;
    std::vector<int> vertsPerFace, faceVerts, creasePairs, corners, holes;
    std::vector<float> creaseWeights, cornerWeights;
    Sdc::Options options;
};

static void fail(std::string const &what) {
    std::fprintf(stderr, "ref_osd: %s\n", what.c_str());
    std::exit(1);
}

static void applyOption(Cage &c, std::string const &name, std::vector<int> const &ints,
                        std::vector<std::string> const &strs) {
    if (name == "interpolateboundary" && ints.size() == 1) {
        c.options.SetVtxBoundaryInterpolation(
            ints[0] == 0   ? Sdc::Options::VTX_BOUNDARY_NONE
            : ints[0] == 1 ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                           : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    } else if (name == "creasemethod" && strs.size() == 1) {
        c.options.SetCreasingMethod(strs[0] == "chaikin" ? Sdc::Options::CREASE_CHAIKIN
                                                         : Sdc::Options::CREASE_UNIFORM);
    } else if (name == "smoothtriangles" && strs.size() == 1) {
        if (strs[0] != "smooth" && strs[0] != "catmark") fail("smoothtriangles: smooth|catmark");
        c.options.SetTriangleSubdivision(strs[0] == "smooth" ? Sdc::Options::TRI_SUB_SMOOTH
                                                             : Sdc::Options::TRI_SUB_CATMARK);
    } else {
        fail("unsupported tag '" + name + "'");
    }
}

static void readTag(Cage &c, std::istringstream &ss) {
    std::string name, counts;
    ss >> name >> counts;
    int ni = 0, nf = 0, ns = 0;
    if (std::sscanf(counts.c_str(), "%d/%d/%d", &ni, &nf, &ns) != 3) fail("bad tag counts");
    std::vector<int> ints(ni);
    std::vector<float> floats(nf);
    std::vector<std::string> strs(ns);
    for (int &i : ints) ss >> i;
    for (float &f : floats) ss >> f;
    for (std::string &s : strs) ss >> s;
    if (!ss) fail("tag '" + name + "' is short of arguments");
    if (name == "crease") {
        for (int k = 0; k + 1 < ni; ++k) {
            c.creasePairs.push_back(ints[k]);
            c.creasePairs.push_back(ints[k + 1]);
            c.creaseWeights.push_back(nf == 1 ? floats[0] : floats[k]);
        }
    } else if (name == "corner") {
        for (int k = 0; k < ni; ++k) {
            c.corners.push_back(ints[k]);
            c.cornerWeights.push_back(nf == 1 ? floats[0] : floats[k]);
        }
    } else if (name == "hole") {
        c.holes.insert(c.holes.end(), ints.begin(), ints.end());
    } else {
        applyOption(c, name, ints, strs);
    }
}

static Cage readObj(char const *path) {
    std::ifstream in(path);
    if (!in) fail(std::string("cannot open ") + path);
    Cage c;
    c.options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    c.options.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
    std::string line;
    while (std::getline(in, line)) {
        line = line.substr(0, line.find('#'));
        std::istringstream ss(line);
        std::string kw;
        if (!(ss >> kw)) continue;
        if (kw == "v") {
            Vec3 p;
            ss >> p.x >> p.y >> p.z;
            c.positions.push_back(p);
        } else if (kw == "f") {
            std::string tok;
            int n = 0;
            while (ss >> tok) {
                int i = std::atoi(tok.c_str());
                if (i < 0) i += (int)c.positions.size() + 1;
                c.faceVerts.push_back(i - 1);
                ++n;
            }
            c.vertsPerFace.push_back(n);
        } else if (kw == "t") {
            readTag(c, ss);
        }
    }
    if (c.vertsPerFace.empty()) fail(std::string("no faces in ") + path);
    return c;
}

static Far::TopologyRefiner *createRefiner(Cage const &c, Sdc::SchemeType scheme) {
    typedef Far::TopologyDescriptor Descriptor;
    Descriptor d;
    d.numVertices = (int)c.positions.size();
    d.numFaces = (int)c.vertsPerFace.size();
    d.numVertsPerFace = c.vertsPerFace.data();
    d.vertIndicesPerFace = c.faceVerts.data();
    d.numCreases = (int)c.creaseWeights.size();
    d.creaseVertexIndexPairs = c.creasePairs.data();
    d.creaseWeights = c.creaseWeights.data();
    d.numCorners = (int)c.cornerWeights.size();
    d.cornerVertexIndices = c.corners.data();
    d.cornerWeights = c.cornerWeights.data();
    d.numHoles = (int)c.holes.size();
    d.holeIndices = c.holes.data();
    Far::TopologyRefiner *r = Far::TopologyRefinerFactory<Descriptor>::Create(
        d, Far::TopologyRefinerFactory<Descriptor>::Options(scheme, c.options));
    if (!r) fail("TopologyRefinerFactory::Create failed");
    return r;
}

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
    Cage c = readObj(argv[1]);
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

    Far::TopologyRefiner *r = createRefiner(c, scheme);
    Far::TopologyRefiner::UniformOptions uo(deep);
    uo.fullTopologyInLastLevel = true;
    r->RefineUniform(uo);
    // limits[l - level]: the limits at level l (local mode: every level from LEVEL to deep;
    // otherwise only deep).
    std::vector<Limits> limits(deep - level + 1);
    limits[deep - level] = limitsAtMaxLevel(*r, c.positions);
    for (int l = level; local && l < deep; ++l) {
        Far::TopologyRefiner *rl = createRefiner(c, scheme);
        Far::TopologyRefiner::UniformOptions ul(l);
        ul.fullTopologyInLastLevel = true;
        rl->RefineUniform(ul);
        limits[l - level] = limitsAtMaxLevel(*rl, c.positions);
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
                (int)c.holes.size(), semiE, semiV, (int)c.positions.size(),
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
