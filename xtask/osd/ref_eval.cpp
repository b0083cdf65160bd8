// ref_eval: OpenSubdiv 3.5's Bfr::Surface evaluation (double precision) at given points of a
// cage, the reference of subdiv's exact evaluation (`subdiv-eval`).
//
//   ref_eval INPUT.obj catmark|loop POINTS.txt [LEVEL]  > values.txt
//
// POINTS.txt has one `FACE U V` a line (subdiv's `--uv` format). For each point it prints one
// line: `p X Y Z du X Y Z dv X Y Z duu X Y Z duv X Y Z dvv X Y Z` (the face's vertex surface,
// Surface::Evaluate with both derivative orders), then ` uv U V uvdu A B uvdv C D` when the cage
// has UVs (its face-varying surface), then ` regular 1|0` (Surface::IsRegular: one regular
// patch, no approximation), or the line `hole` for a face without a limit surface. LEVEL
// (default 10) is the approximation level for smooth and sharp features
// (SurfaceFactory::Options::SetApproxLevelSmooth/Sharp): Bfr refines irregular faces that
// deep around their irregular features and approximates there with Gregory patches.
//
// Build: g++ -O2 -std=c++14 ref_eval.cpp -I/usr/include -losdCPU -o ref_eval

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include "obj_cage.h"

static char const *const TOOL = "ref_eval";

static void print3(char const *name, double const *v) {
    std::printf(" %s %.17g %.17g %.17g", name, v[0], v[1], v[2]);
}

int main(int argc, char **argv) {
    using namespace OpenSubdiv;
    if (argc < 4) objcage::fail(TOOL, "usage: ref_eval INPUT.obj catmark|loop POINTS.txt [LEVEL]");
    objcage::Cage c = objcage::readObj(argv[1], TOOL);
    bool loop = std::string(argv[2]) == "loop";
    int level = argc > 4 ? std::atoi(argv[4]) : 10;
    Far::TopologyRefiner *r =
        objcage::createRefiner(c, loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, TOOL);

    typedef Bfr::RefinerSurfaceFactory<> Factory;
    Factory::Options options;
    options.SetApproxLevelSmooth(level).SetApproxLevelSharp(level);
    if (c.hasUvs()) options.SetDefaultFVarID(0);
    Factory factory(*r, options);

    std::ifstream in(argv[3]);
    if (!in) objcage::fail(TOOL, std::string("cannot open ") + argv[3]);
    typedef Bfr::Surface<double> Surface;
    Surface surface, uvSurface;
    int current = -1;
    bool valid = false;
    std::vector<double> patch, uvPatch;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ss(line);
        int face;
        double uv[2];
        if (!(ss >> face >> uv[0] >> uv[1])) continue;
        if (face != current) {
            current = face;
            valid = factory.InitVertexSurface(face, &surface);
            if (valid) {
                patch.resize(surface.GetNumPatchPoints() * 3);
                surface.PreparePatchPoints(c.positions.data(), Surface::PointDescriptor(3),
                                           patch.data(), Surface::PointDescriptor(3));
            }
            if (valid && c.hasUvs()) {
                factory.InitFaceVaryingSurface(face, &uvSurface);
                uvPatch.resize(uvSurface.GetNumPatchPoints() * 2);
                uvSurface.PreparePatchPoints(c.uvs.data(), Surface::PointDescriptor(2),
                                             uvPatch.data(), Surface::PointDescriptor(2));
            }
        }
        if (!valid) {
            std::printf("hole\n");
            continue;
        }
        double d[6][3];
        surface.Evaluate(uv, patch.data(), Surface::PointDescriptor(3), d[0], d[1], d[2], d[3],
                         d[4], d[5]);
        char const *names[6] = {"p", "du", "dv", "duu", "duv", "dvv"};
        std::printf("%s %.17g %.17g %.17g", names[0], d[0][0], d[0][1], d[0][2]);
        for (int k = 1; k < 6; ++k) print3(names[k], d[k]);
        if (c.hasUvs()) {
            double t[3][2];
            uvSurface.Evaluate(uv, uvPatch.data(), Surface::PointDescriptor(2), t[0], t[1], t[2]);
            std::printf(" uv %.17g %.17g uvdu %.17g %.17g uvdv %.17g %.17g", t[0][0], t[0][1],
                        t[1][0], t[1][1], t[2][0], t[2][1]);
        }
        std::printf(" regular %d\n", surface.IsRegular() ? 1 : 0);
    }
    delete r;
    return 0;
}
