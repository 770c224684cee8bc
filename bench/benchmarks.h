// benchmarks.h: the speed/accuracy trade of the node, measured: ns per evaluation (and per
// sample + pdf) of every fidelity tier and lobe set, beside the baselines users would otherwise
// pick (Lambert, Beckmann Cook-Torrance, the MaterialX-style retroreflective GGX), with each
// row's error against the double reference. Used by the retroprism_bench binary (Google
// Benchmark's own output) and by `retroprism bench` (the trade table).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "prismatic_retroreflector.h"

namespace retroprism::bench {

// A variant of the node prepared for one material: f per lobe (surface, retro, diffuse) at
// local directions (unit, normal +z), computed in the variant's own precision.
using LocalEval = std::function<void(const glm::dvec3& wi, const glm::dvec3& wo, glm::dvec3 f[3])>;

struct Row {
    std::string name;   // the Google Benchmark name of its eval benchmark
    std::string tier;   // reference, exact, fast, or baseline
    std::string lobes;  // surface+retro+diffuse, retro+diffuse, retro, ...
    std::string config; // material and how the code is specialised
    bool baseline = false;
    bool has_sample = false;
    int mask = 0;     // the lobes the row has: 1 surface, 2 retro, 4 diffuse
    Params material;  // the row's material (its modes are the ones the variant fixes)
    Params reference; // the same material for the double reference (fidelity exact)
    // The row's variant prepared for material p (p's modes must be the row's); empty for
    // baselines, which are other models.
    std::function<LocalEval(const Params& p)> make_eval;
};

// The rows, in table order. Registers their Google Benchmark benchmarks (eval, eval + pdf and,
// where the row has one, sample + pdf) the first time it is called.
const std::vector<Row>& rows();

// Evaluations per benchmark iteration (the direction-pair set's size).
constexpr int kPairs = 1024;

// A row of two timings of one material (the node's construction, a shading point): its name,
// its material and the names of its two Google Benchmark benchmarks.
struct PairedRow {
    std::string name;
    std::string config;
    std::string first, second;
};

// Making a node (PrismaticRetroreflector<float>) of a material whose azimuth averages the node
// keeps as series (canted cubes; uncoated ones in the exact tier): benchmark "construct/<name>"
// makes a node of a material not made before each time (its ior one float step apart from the
// last over 1000 values, more than the series the process keeps), "construct/<name>_kept" one of
// the same material each time (its series kept by azimuth_series). Registered with rows().
const std::vector<PairedRow>& construction_rows();

// A shading point as a path tracer visits it: kShadingLights light samples evaluated (eval: f and
// the sampling pdf, for multiple importance sampling) and one BSDF sample, all at one incident
// direction, through the float node's API (PrismaticRetroreflector<float>): benchmark
// "shading/<name>" passes wi to every call, "shading/<name>_state" makes the node's incident state
// once per point (incident(wi)) and passes it. Over kPairs points (the rows' incident
// directions). Registered with rows().
constexpr int kShadingLights = 4;
const std::vector<PairedRow>& shading_rows();

} // namespace retroprism::bench
