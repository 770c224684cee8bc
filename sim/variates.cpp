// variates.cpp: the tables of sim/variates.h, computed at start-up.
#include "variates.h"

#include "prism_core.h"

namespace retroprism {
namespace sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr long double kPiL = 3.141592653589793238462643383279502884L;

// The ziggurat of density f (decreasing on [0, inf), f(0) = 1) with kZigguratLayers layers of
// equal area v (Marsaglia & Tsang 2000, section 2): from x[1] = R and v = R f(R) + tail(R) (the
// base layer), x[i + 1] = f^-1(f(x[i]) + v / x[i]), in long double. R is the root of the top
// layer's closure, x[N - 1] (1 - f(x[N - 1])) = v, found by bisection in long double and written
// below to 21 digits, so that start-up builds each table in one pass; tests/sim/test_variates.cpp
// finds R again (and Marsaglia & Tsang's for 256 layers) and checks every layer's area.
template <class F, class FInverse, class Tail>
Ziggurat make_ziggurat(long double r, F f, FInverse fInverse, Tail tail) {
    constexpr int n = kZigguratLayers;
    const long double v = r * f(r) + tail(r);
    Ziggurat z{};
    z.r = double(r);
    z.v = double(v);
    z.x[0] = double(v / f(r));
    z.x[1] = double(r);
    long double x = r;
    for (int i = 1; i < n - 1; ++i) {
        x = fInverse(f(x) + v / x);
        z.x[i + 1] = double(x);
    }
    z.x[n] = 0.0;
    for (int i = 0; i <= n; ++i)
        z.f[i] = double(f(z.x[i]));
    z.f[0] = double(f(r));
    return z;
}

Ziggurat make_normal() {
    return make_ziggurat(
        4.03884984610950454123L, [](long double x) { return std::exp(-0.5L * x * x); },
        [](long double y) { return std::sqrt(-2.0L * std::log(y)); },
        [](long double r) { return std::sqrt(0.5L * kPiL) * std::erfc(r / std::sqrt(2.0L)); });
}

Ziggurat make_exponential() {
    return make_ziggurat(
        9.25616454426554368523L, [](long double x) { return std::exp(-x); },
        [](long double y) { return -std::log(y); }, [](long double r) { return std::exp(-r); });
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
