// answer.h: what a query asks of the node (query.h), answered: the lobes and the pdf at each
// direction pair, and the C++ node's own answer in double or float (the cpp-double and
// cpp-float backends, and what fuzz_query checks without the GL backends).
#pragma once

#include <array>
#include <vector>

#include "query.h"

namespace retroprism {

// The node's per-lobe BRDF (RGB, 1/sr, no cosine) and the sampling pdf at one direction pair.
struct BackendResult {
    std::array<double, 3> f{}; // the sum of the lobes, in the backend's own precision
    std::array<double, 3> surface{};
    std::array<double, 3> retro{};
    std::array<double, 3> diffuse{};
    double pdf = 0; // NaN: the backend has no pdf (a MaterialX shader has none)
};

// PrismaticRetroreflector<Real> with material p at each pair, the directions rounded to Real
// (defined for float and double).
template <class Real>
std::vector<BackendResult> evaluate_node(const Params& p, const std::vector<DirectionPair>& pairs);

} // namespace retroprism
