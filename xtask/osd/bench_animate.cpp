// bench_animate: OpenSubdiv 3.5 (Far, CPU, float) updating the limit surface of a moving cage,
// the case its stencil tables are made for.
//
//   bench_animate INPUT.obj DEPTH FRAMES [catmark|loop]
//
// setup    (timed apart) the LimitStencilTable of every level-DEPTH vertex, each distinct point
//          once, built once from the cage's topology, exactly as bench_osd's stencil path
//          (Create + RefineAdaptive(isolation DEPTH) + LimitStencilTableFactory::Create).
// frame    the cage swayed (untimed): every point moves along the bounding box's next axis after
//          its longest by a twentieth of the box's diagonal times sin(2 pi (frame / FRAMES + h)),
//          h its height along the longest axis, 0 to 1 over the box (subdiv_mesh::sway, the
//          frames `subdiv bench animate` times); then, timed, UpdateValues + UpdateDerivs on the
//          swayed points and the normals normalize(du x dv), one thread.
//
// One line a frame, then the machine-readable last line:
//   osd_animate points=<n> frames=<n> update_ms_median=<f> points_per_s=<f> stencil_setup_ms=<f>

#define BENCH_OSD_NO_MAIN
#include "bench_osd.cpp"

// One frame of the sway (see the header); `rest` is the cage as read.
static void sway(std::vector<Vec3> const &rest, int frame, int frames, std::vector<Vec3> &out) {
    float lo[3] = {rest[0].x, rest[0].y, rest[0].z}, hi[3] = {lo[0], lo[1], lo[2]};
    for (Vec3 const &p : rest) {
        float q[3] = {p.x, p.y, p.z};
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], q[i]);
            hi[i] = std::max(hi[i], q[i]);
        }
    }
    float ext[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    int a = 0;
    for (int i = 1; i < 3; ++i)
        if (ext[i] > ext[a]) a = i;
    int b = (a + 1) % 3;
    float amplitude = 0.05f * std::sqrt(ext[0] * ext[0] + ext[1] * ext[1] + ext[2] * ext[2]);
    float phase = (float)frame / (float)std::max(frames, 1);
    float height = std::max(ext[a], 1.17549435e-38f);
    out.resize(rest.size());
    for (size_t k = 0; k < rest.size(); ++k) {
        float q[3] = {rest[k].x, rest[k].y, rest[k].z};
        float h = (q[a] - lo[a]) / height;
        q[b] += amplitude * std::sin(6.28318531f * (phase + h));
        out[k].x = q[0];
        out[k].y = q[1];
        out[k].z = q[2];
    }
}

int main(int argc, char **argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: bench_animate INPUT.obj DEPTH FRAMES [catmark|loop]\n");
        return 2;
    }
    Cage c = readObj(argv[1]);
    int depth = std::atoi(argv[2]);
    int frames = std::atoi(argv[3]);
    if (argc > 4 && std::string(argv[4]) == "loop") c.scheme = Sdc::SCHEME_LOOP;
    if (depth < 1 || depth > 10 || frames < 1) fail("DEPTH must be 1..10 and FRAMES >= 1");

    Clock::time_point t0 = Clock::now();
    Far::TopologyRefiner *r = createRefiner(c);
    r->RefineAdaptive(Far::TopologyRefiner::AdaptiveOptions(depth));
    std::vector<std::vector<float> > us, vs;
    locations(*r, depth, c.scheme == Sdc::SCHEME_LOOP, us, vs);
    Far::LimitStencilTableFactory::LocationArrayVec locs(us.size());
    for (size_t f = 0; f < us.size(); ++f) {
        locs[f].ptexIdx = (int)f;
        locs[f].numLocations = (int)us[f].size();
        locs[f].s = us[f].data();
        locs[f].t = vs[f].data();
    }
    Far::LimitStencilTable const *table = Far::LimitStencilTableFactory::Create(*r, locs);
    delete r;
    double setup = since(t0);

    size_t n = (size_t)table->GetNumStencils();
    std::vector<Vec3> cage, pos(n), du(n), dv(n), nrm(n);
    Vec3 *p = pos.data(), *u = du.data(), *v = dv.data();
    std::vector<double> times;
    for (int frame = 0; frame < frames; ++frame) {
        sway(c.positions, frame, frames, cage);
        Clock::time_point t = Clock::now();
        table->UpdateValues(cage.data(), p);
        table->UpdateDerivs(cage.data(), u, v);
        for (size_t i = 0; i < n; ++i) nrm[i] = unitCross(du[i], dv[i]);
        double e = since(t);
        times.push_back(e);
        std::printf("frame=%d update_ms=%.3f points=%zu\n", frame, e * 1e3, n);
    }
    delete table;
    double m = median(times);
    std::printf("osd_animate points=%zu frames=%d update_ms_median=%.3f points_per_s=%.0f stencil_setup_ms=%.3f\n",
                n, frames, m * 1e3, n / m, setup * 1e3);
    return 0;
}
