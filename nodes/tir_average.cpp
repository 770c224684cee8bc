// tir_average.cpp: the exact tier's azimuth average of E = A R1 R2 R3 for uncoated prisms at one
// ior as piecewise Chebyshev series (the layout rp_tir_average_series reads, prism_core.inc), so
// that the node evaluates it in a few tens of operations instead of integrating over azimuth
// (rp_retro_fraction_averaged_exact) at every call.
//
// The series interpolates the integral itself at Chebyshev points of each interval. The
// intervals end where the integrand's break points appear, vanish or cross the ends of the
// integrated sixth of a turn (E(t) is smooth between, kinked at some of them: the onset of total
// internal reflection on a face, the ERA's corners); each interval is halved until the series
// matches the integral at the points between its nodes to within kTolerance.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "prismatic_retroreflector.h"

namespace retroprism {

namespace {

constexpr int kTerms = f64::RP_TIR_AVERAGE_TERMS;
// Largest difference between the series and the integral accepted at the check points of an
// interval: 1e-9 of the largest value on the interval, or 1e-12 of E's largest value at this
// ior where that is more (near the ends of E's support, where E falls to 0). Relative, because
// near eta = 1 E is below 1e-14 and the backends must still agree on it; far below the
// integral's own error (5.6e-7 absolute, the Gauss-Legendre rule's) and a float's rounding.
constexpr double kRelativeTolerance = 1e-8;
constexpr double kFloorTolerance = 1e-11;
// Intervals narrower than this are kept whatever their error (a kink the break points do not
// mark: the series then holds the integral's values at the kink's two sides' nodes).
constexpr double kMinWidth = 1e-7;
// Samples of t that locate a change of the break count before bisection.
constexpr int kScanPoints = 4096;
// Samples of t that find E's largest value at an ior (the scale of kFloorTolerance).
constexpr int kScalePoints = 32;

double integral(double t, double eta) {
    return f64::rp_retro_fraction_averaged_exact(t, eta, true);
}

// t in (0, tMax) where the number of azimuth break points changes, to double precision.
std::vector<double> structure_changes(double eta, double tMax) {
    std::vector<double> out;
    auto count = [&](double t) { return f64::rp_tir_average_breaks(t, eta); };
    double prevT = 0.0;
    int prevN = count(prevT);
    for (int i = 1; i <= kScanPoints; ++i) {
        const double t = tMax * i / kScanPoints;
        const int n = count(t);
        if (n != prevN) {
            double lo = prevT, hi = t;
            for (int k = 0; k < 60 && hi - lo > 1e-15; ++k) {
                const double mid = 0.5 * (lo + hi);
                (count(mid) == prevN ? lo : hi) = mid;
            }
            const double at = 0.5 * (lo + hi);
            if (at > kMinWidth && at < tMax - kMinWidth) out.push_back(at);
        }
        prevT = t;
        prevN = n;
    }
    return out;
}

struct Piece {
    double lo, hi;
    std::array<double, kTerms> c;
    double largest; // of |E| at the nodes
};

// The series of E over [lo, hi] through its values at the kTerms Chebyshev points of the first
// kind (Trefethen, Approximation Theory and Approximation Practice, ch. 3: the discrete cosine
// transform of the values).
Piece fit(double lo, double hi, double eta) {
    Piece p{lo, hi, {}, 0.0};
    std::array<double, kTerms> f;
    for (int k = 0; k < kTerms; ++k) {
        const double u = std::cos(M_PI * (k + 0.5) / kTerms);
        f[size_t(k)] = integral(0.5 * (lo + hi) + 0.5 * (hi - lo) * u, eta);
        p.largest = std::max(p.largest, std::abs(f[size_t(k)]));
    }
    for (int j = 0; j < kTerms; ++j) {
        double s = 0.0;
        for (int k = 0; k < kTerms; ++k)
            s += f[size_t(k)] * std::cos(M_PI * j * (k + 0.5) / kTerms);
        p.c[size_t(j)] = (j == 0 ? 1.0 : 2.0) * s / kTerms;
    }
    return p;
}

double series_at(const Piece& p, double t) {
    const double u = (2.0 * t - p.lo - p.hi) / (p.hi - p.lo);
    double b1 = 0.0, b2 = 0.0;
    for (int j = kTerms - 1; j >= 1; --j) {
        const double b0 = p.c[size_t(j)] + 2.0 * u * b1 - b2;
        b2 = b1;
        b1 = b0;
    }
    return p.c[0] + u * b1 - b2;
}

// Largest difference from the integral at the interval's ends and the points halfway (in angle)
// between its nodes, where an interpolant's error peaks.
double check_error(const Piece& p, double eta) {
    double worst = 0.0;
    for (int k = 0; k <= kTerms; ++k) {
        const double u = std::cos(M_PI * k / kTerms);
        const double t = 0.5 * (p.lo + p.hi) + 0.5 * (p.hi - p.lo) * u;
        worst = std::max(worst, std::abs(series_at(p, t) - integral(t, eta)));
    }
    return worst;
}

// Appends [lo, hi]'s series, halved until within tolerance (floor: the absolute part); the
// largest error accepted, relative to the tolerance, goes to worst.
void refine(double lo, double hi, double eta, double floor, std::vector<Piece>& out,
            double& worst) {
    Piece p = fit(lo, hi, eta);
    const double err = check_error(p, eta);
    const double tolerance = std::max(kRelativeTolerance * p.largest, floor);
    if (err <= tolerance || hi - lo <= kMinWidth) {
        worst = std::max(worst, tolerance > 0.0 ? err / tolerance : err > 0.0 ? INFINITY : 0.0);
        out.push_back(p);
        return;
    }
    const double mid = 0.5 * (lo + hi);
    refine(lo, mid, eta, floor, out, worst);
    refine(mid, hi, eta, floor, out, worst);
}

} // namespace

TirAverageSeries tir_average_series(double eta) {
    const double tMax = f64::RP_ERA_TAN_MAX;
    std::vector<double> ends = {0.0};
    for (double t : structure_changes(eta, tMax))
        ends.push_back(t);
    ends.push_back(tMax);
    double largest = 0.0;
    for (int i = 0; i <= kScalePoints; ++i)
        largest = std::max(largest, std::abs(integral(tMax * i / kScalePoints, eta)));
    std::vector<Piece> pieces;
    TirAverageSeries s;
    for (size_t i = 0; i + 1 < ends.size(); ++i)
        refine(ends[i], ends[i + 1], eta, kFloorTolerance * largest, pieces, s.max_check_error);
    s.data.push_back(double(pieces.size()));
    s.data.push_back(pieces.front().lo);
    for (const Piece& p : pieces)
        s.data.push_back(p.hi);
    for (const Piece& p : pieces)
        s.data.insert(s.data.end(), p.c.begin(), p.c.end());
    return s;
}

} // namespace retroprism
