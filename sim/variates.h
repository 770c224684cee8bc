// variates.h: the simulator's random variates and its Smith Lambda, cheap enough for its inner
// loops (sim/microgeometry.cpp), each drawing from the one RNG (util/rng.h):
//  - pairs of 32-bit uniform variates from one 64-bit draw, for decisions and positions;
//  - standard normal and exponential variates by the ziggurat method (Marsaglia & Tsang 2000,
//    "The ziggurat method for generating random variables", J. Stat. Softw. 5(8)), 1024 layers,
//    the layer index from the low 10 bits of a 64-bit draw and the abscissa from its high 53
//    (disjoint bits, the remedy of Doornik 2005 for the correlation of the original); exact
//    (rejection), no exponential or logarithm on 99.6% (normal) and 99.4% (exponential) of the
//    draws;
//  - the Smith Lambda of the Beckmann surface (the core's rp_beckmann_lambda_of_a, MODEL.md
//    section 1) by piecewise Chebyshev interpolation of g(a) = 2 a Lambda(a) (smooth and positive
//    on [0, 9], where g(0) = 1/sqrt(pi)), fitted at start-up to the core's function itself, so
//    that the formula stays written once; relative error at most kLambdaMaxRelError (measured on
//    a dense grid by tests/sim/test_sim.cpp; the interpolation error below says why a dense
//    grid finds the maximum).
#pragma once

#include <cmath>
#include <cstdint>

#include "rng.h"

namespace retroprism {
namespace sim {

// ---- Uniform pairs ------------------------------------------------------------------------------
// Two uniform variates of [0, 1) from one draw: the high and the low 32 bits of the generator's
// output (xoshiro256**: every bit of full quality), for the decisions and positions where a
// resolution of 2^-32 is immaterial. A Russian roulette on probability p decided with one of them
// happens with a probability within 2^-32 (2.3e-10) of p, and a point drawn with them is within
// 2^-32 of a uniform one in each coordinate: changes to any tallied fraction far below its
// standard error (above 1e-7 for a fraction of 1e-2 even at the CLI's 1e12 rays).
struct UniformPair {
    double u, v;
};
inline UniformPair uniform_pair_of(std::uint64_t bits) {
    return {double(bits >> 32) * 0x1.0p-32, double(bits & 0xffffffffu) * 0x1.0p-32};
}
inline UniformPair uniform_pair(Rng& rng) {
    return uniform_pair_of(rng.next());
}

// ---- Ziggurat tables (sim/variates.cpp) ---------------------------------------------------------
// Layer i in [0, kZigguratLayers) of the density f under the curve, each of area V: x[0] =
// V / f(R) (the base layer with the tail beyond R, as a rectangle of the same area), x[1] = R,
// x[kZigguratLayers] = 0; f[i] = f(x[i]). More layers make the rectangles' share of each layer,
// where a draw is accepted at once, larger: 98.5% of normal and 97.8% of exponential draws with
// 256 layers, 99.6% and 99.4% with 1024 (tests/sim/test_variates.cpp; the share of the
// wavefront's rays completed one at a time falls with them).
constexpr int kZigguratLayers = 1024;
constexpr std::uint64_t kZigguratMask = kZigguratLayers - 1; // the layer's bits of a draw
struct Ziggurat {
    double x[kZigguratLayers + 1];
    double f[kZigguratLayers + 1];
    double r, v;
};
extern const Ziggurat kZigguratNormal;      // f(x) = exp(-x^2 / 2)
extern const Ziggurat kZigguratExponential; // f(x) = exp(-x)

// The ziggurats' first try with one 64-bit draw `bits`, for code that draws in bulk
// (sim/wavefront.cpp): true, with the variate in x, when the draw falls inside its layer's
// rectangle under the curve (99.6% of normal, 99.4% of exponential draws); otherwise the variate
// is normal_variate_from / exponential_variate_from of the same bits, which go on with the wedge,
// the tail and fresh draws from the generator.
inline bool normal_first_try(std::uint64_t bits, double& x) {
    const Ziggurat& z = kZigguratNormal;
    const std::int64_t i = std::int64_t(bits & kZigguratMask); // 64 bits wide: a gather's index
    x = (double(bits >> 11) * 0x1.0p-52 - 1.0) * z.x[i];       // [-x_i, x_i)
    return std::abs(x) < z.x[i + 1];
}
inline bool exponential_first_try(std::uint64_t bits, double& x) {
    const Ziggurat& z = kZigguratExponential;
    const std::int64_t i = std::int64_t(bits & kZigguratMask);
    x = double(bits >> 11) * 0x1.0p-53 * z.x[i]; // [0, x_i)
    return x < z.x[i + 1];
}

// A standard normal variate N(0, 1) whose first draw is `bits`.
template <class R>
double normal_variate_from(std::uint64_t bits, R& rng) {
    const Ziggurat& z = kZigguratNormal;
    for (;; bits = rng.next()) {
        double x;
        if (normal_first_try(bits, x)) return x; // inside the layer's rectangle under the curve
        const unsigned i = unsigned(bits & kZigguratMask);
        if (i == 0) {
            // The tail beyond R (Marsaglia 1964): a = -log(U1) / R, b = -log(U2), accepted when
            // 2 b >= a^2; then R + a has the tail's density.
            double a, b;
            do {
                a = -std::log(rng.uniform_open()) / z.r;
                b = -std::log(rng.uniform_open());
            } while (b + b < a * a);
            return x < 0 ? -(z.r + a) : z.r + a;
        }
        // The wedge: a uniform height in the layer under the curve.
        if (z.f[i] + rng.uniform() * (z.f[i + 1] - z.f[i]) < std::exp(-0.5 * x * x)) return x;
    }
}
inline double normal_variate(Rng& rng) {
    return normal_variate_from(rng.next(), rng);
}

// A standard exponential variate Exp(1) (density exp(-x), x >= 0) whose first draw is `bits`.
template <class R>
double exponential_variate_from(std::uint64_t bits, R& rng) {
    const Ziggurat& z = kZigguratExponential;
    double base = 0; // the tail is R plus an exponential variate (memorylessness)
    for (;; bits = rng.next()) {
        double x;
        if (exponential_first_try(bits, x)) return base + x;
        const unsigned i = unsigned(bits & kZigguratMask);
        if (i == 0) {
            base += z.r;
            continue;
        }
        if (z.f[i] + rng.uniform() * (z.f[i + 1] - z.f[i]) < std::exp(-x)) return base + x;
    }
}
inline double exponential_variate(Rng& rng) {
    return exponential_variate_from(rng.next(), rng);
}

// ---- Smith Lambda -------------------------------------------------------------------------------
// g(a) = 2 a Lambda(a) on [0, kLambdaCut] in kLambdaPieces intervals of width 1 / kLambdaScale,
// a polynomial of degree kLambdaDegree in t in [-1, 1] on each (interpolation at its Chebyshev
// nodes). The interpolation error is g^(n+1)(xi) / (2^n (n+1)!) (h/2)^(n+1) (n = kLambdaDegree,
// h the width), a smooth function of a between the nodes: a grid of 64 points per interval
// resolves its maximum.
constexpr double kLambdaCut = 9.0; // the core's RP_LAMBDA_EXACT_CUT: Lambda = 0 beyond
constexpr int kLambdaScale = 16;
constexpr int kLambdaPieces = 144; // kLambdaCut * kLambdaScale
constexpr int kLambdaDegree = 8;
// Largest relative error of beckmann_lambda_table against the core's Lambda over (0, 9]: the
// measured 8.8e-11 (near a = 9; below 3e-11 for a < 8, 1e-14 for a < 3) rounded up. In the walk
// Lambda is an exponent, G1 = C1^Lambda, so each hit or escape probability changes by a relative
// 1e-10 |Lambda log C1| at most: far below any Monte Carlo error the simulator can reach.
constexpr double kLambdaMaxRelError = 1e-10;
struct LambdaTable {
    double c[kLambdaPieces][kLambdaDegree + 1]; // monomial coefficients in t, lowest first
};
extern const LambdaTable kLambdaTable;

// g(a) = 2 a Lambda(a) for 0 <= a <= kLambdaCut (any other a reads a valid row: the table is read
// whatever a is, so that vectorised code reads it unconditionally, sim/wavefront.cpp).
inline double beckmann_lambda_g(double a) {
    const double s = (a <= kLambdaCut ? a : 0.0) * kLambdaScale;
    const std::int64_t i = s < double(kLambdaPieces) ? std::int64_t(s) : kLambdaPieces - 1;
    const double t = 2.0 * (s - double(i)) - 1.0;
    // Indexed from the table's start, 64 bits wide (a gather's form in vectorised code).
    const double* c = &kLambdaTable.c[0][0];
    const std::int64_t row = i * (kLambdaDegree + 1);
    double g = c[row + kLambdaDegree];
#pragma GCC unroll 32
    for (int k = kLambdaDegree - 1; k >= 0; --k)
        g = g * t + c[row + k];
    return g;
}

// Lambda(a), a = 1 / (alpha tan(theta)) > 0; 0 for a > kLambdaCut (as the core).
inline double beckmann_lambda_table(double a) {
    return a <= kLambdaCut ? beckmann_lambda_g(a) / (a + a) : 0.0;
}

} // namespace sim
} // namespace retroprism
