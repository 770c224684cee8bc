// minimize.h: the derivative-free minimiser of the fitters.
#pragma once

#include <functional>
#include <limits>
#include <vector>

namespace retroprism {

struct NmResult {
    std::vector<double> x;
    double f = std::numeric_limits<double>::infinity();
    int evaluations = 0;
};

// Nelder-Mead in n dimensions from x0 (initial simplex: x0 and x0 + step along each axis),
// standard coefficients (reflection 1, expansion 2, contraction 0.5, shrink 0.5); stops when the
// simplex is smaller than 1e-4 with values within 1e-10 relative, smaller than 1e-7, or after
// maxEval evaluations. Returns the best vertex.
NmResult nelder_mead(const std::function<double(const std::vector<double>&)>& f,
                     std::vector<double> x0, double step, int maxEval);

} // namespace retroprism
