// benchmarks.h: the speed/accuracy trade of the node, measured: ns per evaluation (and per
// sample + pdf) of every fidelity tier and lobe set, beside the baselines users would otherwise
// pick (Lambert, Beckmann Cook-Torrance, the MaterialX-style retroreflective GGX), with each
// row's error against the double reference. Used by the retroprism_bench binary (Google
// Benchmark's own output) and by `retroprism bench` (the trade table).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace retroprism::bench {

struct Row {
    std::string name;   // the Google Benchmark name of its eval benchmark
    std::string tier;   // reference, exact, fast, or baseline
    std::string lobes;  // surface+retro+diffuse, retro+diffuse, retro, ...
    std::string config; // material and how the code is specialised
    bool baseline = false;
    bool has_sample = false;
    // Relative L1 error against the double reference over the benchmark's direction pairs
    // (sum |f - f_ref| / sum |f_ref| over the RGB of the lobes the row has); negative for
    // baselines, which are other models.
    std::function<double()> error;
};

// The rows, in table order. Registers their Google Benchmark benchmarks (eval and, where the
// row has one, sample + pdf) the first time it is called.
const std::vector<Row>& rows();

// Evaluations per benchmark iteration (the direction-pair set's size).
constexpr int kPairs = 1024;

} // namespace retroprism::bench
