// obj_cage.h: an OBJ cage with OpenSubdiv's tag lines, for the harnesses that evaluate it with
// OpenSubdiv 3.5 (ref_eval.cpp, bench_eval.cpp).
//
// Reads `v`, `vt`, `f v[/vt[/vn]]` and the tags crease, corner, hole, interpolateboundary,
// creasemethod, facevaryinginterpolateboundary and smoothtriangles (spelled as OpenSubdiv's
// regression/common/far_utils.h spells them: `t smoothtriangles 0/0/1 smooth|catmark`), and
// makes the base-level Far::TopologyRefiner (with the UVs as face-varying channel 0).

#ifndef SUBDIV_OBJ_CAGE_H
#define SUBDIV_OBJ_CAGE_H

#include <opensubdiv/far/topologyDescriptor.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace objcage {

using namespace OpenSubdiv;

inline void fail(char const *tool, std::string const &what) {
    std::fprintf(stderr, "%s: %s\n", tool, what.c_str());
    std::exit(1);
}

struct Cage {
    std::vector<double> positions;  // x y z per vertex
    std::vector<double> uvs;        // u v per value
    std::vector<int> vertsPerFace, faceVerts, faceUvs, creasePairs, corners, holes;
    std::vector<float> creaseWeights, cornerWeights;
    Sdc::Options options;
    int numVertices() const { return (int)positions.size() / 3; }
    bool hasUvs() const { return !uvs.empty() && faceUvs.size() == faceVerts.size(); }
};

inline void readTag(Cage &c, std::istringstream &ss, char const *tool) {
    std::string name, counts;
    ss >> name >> counts;
    int ni = 0, nf = 0, ns = 0;
    if (std::sscanf(counts.c_str(), "%d/%d/%d", &ni, &nf, &ns) != 3) fail(tool, "bad tag counts");
    std::vector<int> ints(ni);
    std::vector<float> floats(nf);
    std::vector<std::string> strs(ns);
    for (int &i : ints) ss >> i;
    for (float &f : floats) ss >> f;
    for (std::string &s : strs) ss >> s;
    if (!ss) fail(tool, "tag '" + name + "' is short of arguments");
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
    } else if (name == "facevaryinginterpolateboundary" && ni == 1) {
        if (ints[0] < 0 || ints[0] > 5) fail(tool, "facevaryinginterpolateboundary: 0..5");
        c.options.SetFVarLinearInterpolation((Sdc::Options::FVarLinearInterpolation)ints[0]);
    } else if (name == "creasemethod" && ns == 1) {
        c.options.SetCreasingMethod(strs[0] == "chaikin" ? Sdc::Options::CREASE_CHAIKIN
                                                         : Sdc::Options::CREASE_UNIFORM);
    } else if (name == "smoothtriangles" && ns == 1) {
        if (strs[0] != "smooth" && strs[0] != "catmark") fail(tool, "smoothtriangles: smooth|catmark");
        c.options.SetTriangleSubdivision(strs[0] == "smooth" ? Sdc::Options::TRI_SUB_SMOOTH
                                                             : Sdc::Options::TRI_SUB_CATMARK);
    } else {
        fail(tool, "unsupported tag '" + name + "'");
    }
}

inline Cage readObj(char const *path, char const *tool) {
    std::ifstream in(path);
    if (!in) fail(tool, std::string("cannot open ") + path);
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
            double x = 0, y = 0, z = 0;
            ss >> x >> y >> z;
            c.positions.insert(c.positions.end(), {x, y, z});
        } else if (kw == "vt") {
            double u = 0, v = 0;
            ss >> u >> v;
            c.uvs.insert(c.uvs.end(), {u, v});
        } else if (kw == "f") {
            std::string tok;
            int n = 0;
            while (ss >> tok) {
                int i = std::atoi(tok.c_str());
                if (i < 0) i += c.numVertices() + 1;
                c.faceVerts.push_back(i - 1);
                size_t slash = tok.find('/');
                if (slash != std::string::npos && slash + 1 < tok.size() && tok[slash + 1] != '/') {
                    int t = std::atoi(tok.c_str() + slash + 1);
                    if (t < 0) t += (int)c.uvs.size() / 2 + 1;
                    c.faceUvs.push_back(t - 1);
                }
                ++n;
            }
            c.vertsPerFace.push_back(n);
        } else if (kw == "t") {
            readTag(c, ss, tool);
        }
    }
    if (c.vertsPerFace.empty()) fail(tool, std::string("no faces in ") + path);
    return c;
}

// The base-level refiner of `c` (the UVs as face-varying channel 0 when it has them).
inline Far::TopologyRefiner *createRefiner(Cage const &c, Sdc::SchemeType scheme, char const *tool) {
    typedef Far::TopologyDescriptor Descriptor;
    Descriptor d;
    d.numVertices = c.numVertices();
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
    Descriptor::FVarChannel uv;
    if (c.hasUvs()) {
        uv.numValues = (int)c.uvs.size() / 2;
        uv.valueIndices = c.faceUvs.data();
        d.numFVarChannels = 1;
        d.fvarChannels = &uv;
    }
    Far::TopologyRefiner *r = Far::TopologyRefinerFactory<Descriptor>::Create(
        d, Far::TopologyRefinerFactory<Descriptor>::Options(scheme, c.options));
    if (!r) fail(tool, "TopologyRefinerFactory::Create failed");
    return r;
}

}  // namespace objcage

#endif
