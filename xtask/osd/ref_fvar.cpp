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
#include "obj_cage.h"

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

static char const *const TOOL = "ref_fvar";

static void fail(std::string const &what) { objcage::fail(TOOL, what); }

int main(int argc, char **argv) {
    if (argc < 3) fail("usage: ref_fvar INPUT.obj LEVEL [catmark|loop] [FVAR] [limit]");
    objcage::Cage c = objcage::readObj(argv[1], TOOL);
    if (!c.hasUvs()) fail("every face corner needs a vt");
    int level = std::atoi(argv[2]);
    Sdc::SchemeType scheme = Sdc::SCHEME_CATMARK;
    if (argc > 3 && std::string(argv[3]) == "loop") scheme = Sdc::SCHEME_LOOP;
    bool limit = argc > 5 && std::string(argv[5]) == "limit";
    if (argc > 4) {
        int k = std::atoi(argv[4]);
        if (k < 0 || k > 5) fail("FVAR: 0..5");
        c.options.SetFVarLinearInterpolation((Sdc::Options::FVarLinearInterpolation)k);
    }
    Far::TopologyRefiner *r = objcage::createRefiner(c, scheme, TOOL);
    Far::TopologyRefiner::UniformOptions uo(level);
    uo.fullTopologyInLastLevel = true;
    r->RefineUniform(uo);
    Far::PrimvarRefinerReal<double> pr(*r);
    std::vector<Uv> cur(c.uvs.size() / 2);
    for (size_t i = 0; i < cur.size(); ++i) cur[i] = Uv{c.uvs[2 * i], c.uvs[2 * i + 1]};
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
