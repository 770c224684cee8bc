// minimize.h: the derivative-free minimisers of the fitters: Nelder-Mead, and the bounded search
// built on it that the ALTA fitter (analysis/fitting.h) and the R_A fitter (analysis/ra_fit.h)
// share.
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

// One variable of search_box: searched in [lo, hi] (lo < hi; lo > 0 when log), on a log scale
// when `log`.
struct BoxVar {
    double lo = 0, hi = 1;
    bool log = false;
};

// The value of logistic coordinate u (any real number): lo + sigmoid(u) (hi - lo), or the same
// on ln x when log. Always inside [lo, hi].
double box_value(const BoxVar& v, double u);
// The logistic coordinate of value x, clamped to 1e-3 of the range inside it.
double box_coordinate(const BoxVar& v, double x);

// The usual starts of search_box: `base` (values), the centre of the box, and the centre with
// each coordinate moved to either side (logistic coordinates -2 and +2: 12% and 88% of the
// range); 2 + 2n starts.
std::vector<std::vector<double>> box_starts(const std::vector<BoxVar>& vars,
                                            const std::vector<double>& base);

// Minimises f (called with values, each within its var's [lo, hi]) over the box by Nelder-Mead
// in logistic coordinates: one run from each start (values; initial simplex step 0.7 in
// coordinates, at most maxEval evaluations), then runs restarted from the best point (step 0.3)
// until one improves it by less than 1e-9 relative, at most `restarts` times. Deterministic: the
// result depends on f, the box and the starts only. Returns the best point as values, its f and
// the evaluations of all runs. With no vars, f is evaluated once at the empty point.
NmResult search_box(const std::function<double(const std::vector<double>&)>& f,
                    const std::vector<BoxVar>& vars, const std::vector<std::vector<double>>& starts,
                    int maxEval, int restarts = 4);

} // namespace retroprism
