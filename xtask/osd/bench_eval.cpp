// bench_eval: OpenSubdiv 3.5's Bfr evaluation throughput, one thread, the counterpart of
// `subdiv bench evaluate` (the evaluation rows of `cargo xtask bench-osd`).
//
//   bench_eval INPUT.obj catmark|loop POINTS.txt RUNS [LEVEL]
//
// POINTS.txt: one `FACE U V` a line. Each run evaluates every point's position and first
// derivatives as a Bfr client does: the points grouped by face (the sort is timed, as subdiv's
// is), and for each face SurfaceFactory::InitVertexSurface, Surface::PreparePatchPoints and
// one Surface::Evaluate per point (double precision, the factory's topology cache on, as by
// default). LEVEL: the approximation levels for smooth and sharp features (default: Bfr's
// defaults, 2 and 6). The factory is built once, outside the timing. Prints `bfr points=<n>
// faces=<n> level=<l> setup_ms=<f> median_ms=<f> min_ms=<f> points_per_s=<f>`.
//
// Build: g++ -O3 -march=native -std=c++14 bench_eval.cpp -losdCPU -o bench_eval

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include <algorithm>
#include <chrono>
#include <numeric>

#include "obj_cage.h"

static char const *const TOOL = "bench_eval";

int main(int argc, char **argv) {
    using namespace OpenSubdiv;
    if (argc < 5) objcage::fail(TOOL, "usage: bench_eval INPUT.obj catmark|loop POINTS.txt RUNS [LEVEL]");
    objcage::Cage c = objcage::readObj(argv[1], TOOL);
    bool loop = std::string(argv[2]) == "loop";
    int runs = std::max(1, std::atoi(argv[4]));
    int level = argc > 5 ? std::atoi(argv[5]) : -1;

    std::ifstream in(argv[3]);
    if (!in) objcage::fail(TOOL, std::string("cannot open ") + argv[3]);
    std::vector<int> faces;
    std::vector<double> uvs;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ss(line);
        int f;
        double u, v;
        if (ss >> f >> u >> v) {
            faces.push_back(f);
            uvs.push_back(u);
            uvs.push_back(v);
        }
    }
    size_t n = faces.size();

    typedef std::chrono::steady_clock Clock;
    auto t0 = Clock::now();
    Far::TopologyRefiner *r =
        objcage::createRefiner(c, loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, TOOL);
    typedef Bfr::RefinerSurfaceFactory<> Factory;
    Factory::Options options;
    if (level >= 0) options.SetApproxLevelSmooth(level).SetApproxLevelSharp(level);
    Factory factory(*r, options);
    double setupMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();

    typedef Bfr::Surface<double> Surface;
    Surface surface;
    std::vector<double> patch, out(n * 9);
    std::vector<size_t> order(n);
    std::vector<double> times;
    size_t used = 0;
    for (int run = 0; run < runs; ++run) {
        auto t = Clock::now();
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(),
                         [&](size_t a, size_t b) { return faces[a] < faces[b]; });
        int current = -1;
        bool valid = false;
        used = 0;
        for (size_t k = 0; k < n; ++k) {
            size_t i = order[k];
            if (faces[i] != current) {
                current = faces[i];
                valid = factory.InitVertexSurface(current, &surface);
                if (valid) {
                    patch.resize(surface.GetNumPatchPoints() * 3);
                    surface.PreparePatchPoints(c.positions.data(), Surface::PointDescriptor(3),
                                               patch.data(), Surface::PointDescriptor(3));
                    ++used;
                }
            }
            if (!valid) continue;
            double *o = &out[i * 9];
            surface.Evaluate(&uvs[i * 2], patch.data(), Surface::PointDescriptor(3), o, o + 3,
                             o + 6);
        }
        times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());
    }
    std::sort(times.begin(), times.end());
    double median = times[times.size() / 2];
    double check = 0.0;
    for (double x : out) check += x;
    std::printf("bfr points=%zu faces=%zu level=%d setup_ms=%.3f median_ms=%.3f min_ms=%.3f "
                "points_per_s=%.0f checksum=%.6g\n",
                n, used, level, setupMs, median, times[0], (double)n / (median * 1e-3), check);
    delete r;
    return 0;
}
