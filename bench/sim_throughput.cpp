// sim_throughput.cpp: rays/s of the microgeometry simulator (sim::simulate) on the configuration
// of `retroprism simulate --theta-i 30 --material M.json` with M.json = {"prism_reflection":
// "tir", "roughness": 0.1}: the standard grids of that incidence, one run, no progress callback
// unless asked. Without OpenImageIO and the CLI's other libraries, so that it runs under
// valgrind (callgrind) and starts at once.
//
// Usage: retroprism_sim_throughput [rays] [threads] [seed] [progress 0|1] [wavefront|scalar]
// Prints rays/s and the fates, and a checksum of every tally (to compare builds for identical
// results).
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "microgeometry.h"

using namespace retroprism;

int main(int argc, char** argv) {
    const double rays = argc > 1 ? std::atof(argv[1]) : 1e6;
    const int threads = argc > 2 ? std::atoi(argv[2]) : 0;
    const std::uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
    const bool progress = argc > 4 && std::atoi(argv[4]) != 0;
    const bool scalar = argc > 5 && std::string(argv[5]) == "scalar";
    Params p;
    p.prism_reflection = f64::RP_PRISM_TIR;
    p.roughness = 0.1;
    const double th = 30.0 * 3.14159265358979323846 / 180.0;
    const sim::dvec3 wi(std::sin(th), 0.0, std::cos(th));
    const sim::Sheet sheet = sim::sheet_from_params(p, 0);
    const std::vector<sim::Grid> grids = sim::standard_grids(sheet, wi);
    sim::RunOptions opt;
    opt.rays = std::uint64_t(rays);
    opt.seed = seed;
    opt.threads = threads;
    if (scalar) opt.tracer = sim::RunOptions::kScalar;
    std::uint64_t calls = 0;
    if (progress) opt.progress = [&calls](std::uint64_t, std::uint64_t) { ++calls; };
    const sim::Run run = sim::simulate(sheet, wi, grids, opt);
    const sim::Tally& t = run.tally;
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
    for (std::uint64_t f : t.fates)
        mix(f);
    mix(t.retro_primary);
    mix(t.retro_multiple);
    mix(t.surface_single);
    mix(t.substrate_hits);
    mix(t.face_transmissions);
    mix(t.internal_reflections);
    for (const auto& g : t.counts)
        for (std::uint64_t c : g)
            mix(c);
    std::printf("%.4g rays/s on %d threads (%.3f s)  fates", run.rays_per_second(), run.threads,
                run.seconds);
    for (int f = 0; f < sim::kFates; ++f)
        std::printf(" %s %" PRIu64, sim::fate_name(f), t.fates[size_t(f)]);
    std::printf("  checksum %016" PRIx64 "\n", h);
    return 0;
}
