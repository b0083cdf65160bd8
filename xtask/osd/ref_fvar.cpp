// ref_fvar: reference face-varying refinement from OpenSubdiv 3.5 (Far, CPU, double precision).
//
//   ref_fvar INPUT.obj LEVEL [catmark|loop] [FVAR] [limit]  > shape.fvar.L<LEVEL>.txt
//
// Reads an OBJ cage with `vt` and `f v/vt` corners and OpenSubdiv's tag lines (crease, corner,
// hole, interpolateboundary, creasemethod, smoothtriangles, facevaryinginterpolateboundary),
// optionally overriding the face-varying linear interpolation with FVAR (0 none .. 5 all),
// refines uniformly to LEVEL with TopologyRefiner::RefineUniform, interpolates the channel
// level by level with PrimvarRefinerReal<double>::InterpolateFaceVarying and prints, for every
// level-LEVEL face in OpenSubdiv's order, `f` and the u v of each corner:
//
//   fvar LEVEL=<l> faces=<n> option=<k>
//   f u0 v0 u1 v1 ...
//
// With `limit`, the values printed are the face-varying limits of the level-LEVEL values
// (PrimvarRefinerReal<double>::LimitFaceVarying), and the header says `fvar-limit`.
//
// Build: g++ -O2 -std=c++14 ref_fvar.cpp -I/usr/include -losdCPU -o ref_fvar

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

struct Uv {
    double u, v;
    void Clear(void * = 0) { u = v = 0.0; }
    void AddWithWeight(Uv const &s, double w) {
        u += w * s.u;
        v += w * s.v;
    }
};

static void fail(std::string const &what) {
    std::fprintf(stderr, "ref_fvar: %s\n", what.c_str());
    std::exit(1);
}

struct Cage {
    int numVerts = 0;
    std::vector<Uv> uvs;
    std::vector<int> vertsPerFace, faceVerts, faceUvs, creasePairs, corners, holes;
    std::vector<float> creaseWeights, cornerWeights;
    Sdc::Options options;
};

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
    } else if (name == "interpolateboundary" && ni == 1) {
        c.options.SetVtxBoundaryInterpolation(
            ints[0] == 0   ? Sdc::Options::VTX_BOUNDARY_NONE
            : ints[0] == 1 ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                           : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    } else if (name == "creasemethod" && ns == 1) {
        c.options.SetCreasingMethod(strs[0] == "chaikin" ? Sdc::Options::CREASE_CHAIKIN
                                                         : Sdc::Options::CREASE_UNIFORM);
    } else if (name == "smoothtriangles" && ns == 1) {
        c.options.SetTriangleSubdivision(strs[0] == "smooth" ? Sdc::Options::TRI_SUB_SMOOTH
                                                             : Sdc::Options::TRI_SUB_CATMARK);
    } else if (name == "facevaryinginterpolateboundary" && ni == 1) {
        if (ints[0] < 0 || ints[0] > 5) fail("facevaryinginterpolateboundary: 0..5");
        c.options.SetFVarLinearInterpolation((Sdc::Options::FVarLinearInterpolation)ints[0]);
    } else {
        fail("unsupported tag '" + name + "'");
    }
}

static int objIndex(std::string const &t, int count) {
    int i = std::atoi(t.c_str());
    return i < 0 ? i + count : i - 1;
}

static Cage readObj(char const *path) {
    std::ifstream in(path);
    if (!in) fail(std::string("cannot open ") + path);
    Cage c;
    c.options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    c.options.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
    c.options.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_CORNERS_ONLY);
    std::string line;
    while (std::getline(in, line)) {
        line = line.substr(0, line.find('#'));
        std::istringstream ss(line);
        std::string kw;
        if (!(ss >> kw)) continue;
        if (kw == "v") {
            ++c.numVerts;
        } else if (kw == "vt") {
            Uv t;
            ss >> t.u >> t.v;
            c.uvs.push_back(t);
        } else if (kw == "f") {
            std::string tok;
            int n = 0;
            while (ss >> tok) {
                size_t slash = tok.find('/');
                if (slash == std::string::npos) fail("face corner without vt: " + tok);
                c.faceVerts.push_back(objIndex(tok.substr(0, slash), c.numVerts));
                c.faceUvs.push_back(objIndex(tok.substr(slash + 1), (int)c.uvs.size()));
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

int main(int argc, char **argv) {
    if (argc < 3) fail("usage: ref_fvar INPUT.obj LEVEL [catmark|loop] [FVAR] [limit]");
    Cage c = readObj(argv[1]);
    int level = std::atoi(argv[2]);
    Sdc::SchemeType scheme = Sdc::SCHEME_CATMARK;
    if (argc > 3 && std::string(argv[3]) == "loop") scheme = Sdc::SCHEME_LOOP;
    bool limit = argc > 5 && std::string(argv[5]) == "limit";
    if (argc > 4) {
        int k = std::atoi(argv[4]);
        if (k < 0 || k > 5) fail("FVAR: 0..5");
        c.options.SetFVarLinearInterpolation((Sdc::Options::FVarLinearInterpolation)k);
    }
    typedef Far::TopologyDescriptor Descriptor;
    Descriptor d;
    d.numVertices = c.numVerts;
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
    Descriptor::FVarChannel ch;
    ch.numValues = (int)c.uvs.size();
    ch.valueIndices = c.faceUvs.data();
    d.numFVarChannels = 1;
    d.fvarChannels = &ch;
    Far::TopologyRefiner *r = Far::TopologyRefinerFactory<Descriptor>::Create(
        d, Far::TopologyRefinerFactory<Descriptor>::Options(scheme, c.options));
    if (!r) fail("TopologyRefinerFactory::Create failed");
    Far::TopologyRefiner::UniformOptions uo(level);
    uo.fullTopologyInLastLevel = true;
    r->RefineUniform(uo);
    Far::PrimvarRefinerReal<double> pr(*r);
    std::vector<Uv> cur = c.uvs;
    for (int l = 1; l <= level; ++l) {
        std::vector<Uv> next(r->GetLevel(l).GetNumFVarValues(0));
        Uv const *src = cur.data();
        Uv *dst = next.data();
        pr.InterpolateFaceVarying(l, src, dst, 0);
        cur.swap(next);
    }
    if (limit) {
        std::vector<Uv> lim(cur.size());
        Uv const *src = cur.data();
        Uv *dst = lim.data();
        pr.LimitFaceVarying(src, dst, 0);
        cur.swap(lim);
    }
    Far::TopologyLevel const &last = r->GetLevel(level);
    std::printf("%s LEVEL=%d faces=%d option=%d\n", limit ? "fvar-limit" : "fvar", level,
                last.GetNumFaces(),
                (int)c.options.GetFVarLinearInterpolation());
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        Far::ConstIndexArray fv = last.GetFaceFVarValues(f, 0);
        std::printf("f");
        for (int k = 0; k < fv.size(); ++k) std::printf(" %.9g %.9g", cur[fv[k]].u, cur[fv[k]].v);
        std::printf("\n");
    }
    delete r;
    return 0;
}
