// brdf_table.h: the tabulated BRDF of `retroprism simulate`: for one incident direction, the
// microgeometry simulation's f per lobe and colour channel as cosine-weighted cell averages
// [1/sr] over the standard grids (sim::standard_grids), with binomial standard errors.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "microgeometry.h"

namespace retroprism::sim {

// The lobes of a table, in this order.
inline const char* const kTableLobes[5] = {"surface", "surface_single", "retro", "diffuse",
                                           "total"};

struct BrdfTable {
    double theta_i_deg = 0, phi_i_deg = 0;
    dvec3 wi;
    std::vector<Grid> grids;
    std::vector<std::vector<double>> projected; // [grid][cell]: projected solid angle [sr]
    // [channel][grid][lobe][cell]: f and its standard error.
    std::array<std::vector<std::array<std::vector<double>, 5>>, 3> f, se;
    // The simulation of each channel; run_of[c]: the channel whose simulation channel c shares
    // (channels with the same diffuse_color share one).
    std::array<Run, 3> runs;
    int run_of[3] = {0, 1, 2};
};

struct TableOptions {
    std::uint64_t rays = 1000000; // per simulated channel
    std::uint64_t seed = 1;
    int threads = 0;
    bool way_up_through_prisms = true; // false: the paper's way up (direct)
    // A progress callback for the simulation of a channel, from its label.
    std::function<RunOptions::Progress(const std::string& label)> progress;
};

// Simulates material p (sanitised) at incidence (theta_i, phi_i) [deg]: one simulation per
// distinct diffuse_color among the channels (the rest of the geometry is grey); specular,
// retro_color and weight multiply the lobes.
BrdfTable tabulate_brdf(const Params& p, double thetaIDeg, double phiIDeg,
                        const TableOptions& options);

} // namespace retroprism::sim
