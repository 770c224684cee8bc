// variates.cpp: the tables of sim/variates.h, computed at start-up.
#include "variates.h"

#include <vector>

#include "prism_core.h"

namespace retroprism {
namespace sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr long double kPiL = 3.141592653589793238462643383279502884L;

// The ziggurat of density f (decreasing on [0, inf), f(0) = 1) with kZigguratLayers layers of
// equal area v (Marsaglia & Tsang 2000, section 2): from x[1] = R and v = R f(R) + tail(R) (the
// base layer), x[i + 1] = f^-1(f(x[i]) + v / x[i]); R is the root of the top layer's closure,
// x[N - 1] (1 - f(x[N - 1])) = v, found by bisection in long double (a larger R makes the layers
// thinner and the top one wider).
template <class F, class FInverse, class Tail>
Ziggurat make_ziggurat(F f, FInverse fInverse, Tail tail) {
    constexpr int n = kZigguratLayers;
    // The top layer's area less v (< 0 where the layers reach f = 1 early: R too small).
    const auto closure = [&](long double r, long double* x) {
        const long double v = r * f(r) + tail(r);
        x[1] = r;
        for (int i = 1; i < n - 1; ++i) {
            const long double y = f(x[i]) + v / x[i];
            if (!(y < 1)) return -v;
            x[i + 1] = fInverse(y);
        }
        return x[n - 1] * (1 - f(x[n - 1])) - v;
    };
    std::vector<long double> x(size_t(n) + 1);
    long double lo = 1, hi = 20;
    for (int k = 0; k < 200 && hi - lo > 1e-17L * hi; ++k) {
        const long double mid = 0.5L * (lo + hi);
        (closure(mid, x.data()) < 0 ? lo : hi) = mid;
    }
    const long double r = hi, v = r * f(r) + tail(r);
    closure(r, x.data());
    Ziggurat z{};
    z.r = double(r);
    z.v = double(v);
    z.x[0] = double(v / f(r));
    for (int i = 1; i < n; ++i)
        z.x[i] = double(x[size_t(i)]);
    z.x[n] = 0.0;
    for (int i = 0; i <= n; ++i)
        z.f[i] = double(f(z.x[i]));
    z.f[0] = double(f(r));
    return z;
}

Ziggurat make_normal() {
    return make_ziggurat(
        [](long double x) { return std::exp(-0.5L * x * x); },
        [](long double y) { return std::sqrt(-2.0L * std::log(y)); },
        [](long double r) { return std::sqrt(0.5L * kPiL) * std::erfc(r / std::sqrt(2.0L)); });
}

Ziggurat make_exponential() {
    return make_ziggurat([](long double x) { return std::exp(-x); },
                         [](long double y) { return -std::log(y); },
                         [](long double r) { return std::exp(-r); });
}

// g(a) = 2 a Lambda(a), Lambda the core's; g(0) = 1 / sqrt(pi).
double lambda_g(double a) {
    return 2.0 * a * f64::rp_beckmann_lambda_of_a(a);
}

// Chebyshev interpolation of g on each interval, as monomial coefficients in t in [-1, 1]
// (T_k expanded by T_{k+1} = 2 t T_k - T_{k-1}, in long double).
LambdaTable make_lambda_table() {
    constexpr int kNodes = kLambdaDegree + 1;
    // Monomial coefficients of T_0 ... T_degree.
    long double tPoly[kNodes][kNodes] = {};
    tPoly[0][0] = 1;
    tPoly[1][1] = 1;
    for (int k = 1; k + 1 < kNodes; ++k)
        for (int j = 0; j < kNodes; ++j)
            tPoly[k + 1][j] = (j > 0 ? 2 * tPoly[k][j - 1] : 0) - tPoly[k - 1][j];
    LambdaTable table{};
    const double half = 0.5 / kLambdaScale;
    for (int piece = 0; piece < kLambdaPieces; ++piece) {
        const double mid = (piece + 0.5) / kLambdaScale;
        long double cheb[kNodes] = {};
        for (int j = 0; j < kNodes; ++j) {
            const double theta = kPi * (j + 0.5) / kNodes;
            const double gj = lambda_g(mid + half * std::cos(theta));
            for (int k = 0; k < kNodes; ++k)
                cheb[k] += (2.0L / kNodes) * gj * std::cos(k * theta);
        }
        cheb[0] *= 0.5L;
        for (int j = 0; j < kNodes; ++j) {
            long double sum = 0;
            for (int k = 0; k < kNodes; ++k)
                sum += cheb[k] * tPoly[k][j];
            table.c[piece][j] = double(sum);
        }
    }
    return table;
}

} // namespace

extern const Ziggurat kZigguratNormal = make_normal();
extern const Ziggurat kZigguratExponential = make_exponential();
extern const LambdaTable kLambdaTable = make_lambda_table();

} // namespace sim
} // namespace retroprism
