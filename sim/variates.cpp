// variates.cpp: the tables of sim/variates.h, computed at start-up.
#include "variates.h"

#include "prism_core.h"

namespace retroprism {
namespace sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The 256-layer ziggurat of density f with tail start r and layer area v (Marsaglia & Tsang
// 2000, section 2): x[i + 1] = f^-1(f(x[i]) + v / x[i]), the top layer's x[256] = 0.
template <class F, class FInverse>
Ziggurat make_ziggurat(double r, double v, F f, FInverse fInverse) {
    Ziggurat z{};
    z.r = r;
    z.x[0] = v / f(r);
    z.x[1] = r;
    for (int i = 1; i < 255; ++i)
        z.x[i + 1] = fInverse(f(z.x[i]) + v / z.x[i]);
    z.x[256] = 0.0;
    for (int i = 0; i <= 256; ++i)
        z.f[i] = f(z.x[i]);
    z.f[0] = f(r);
    return z;
}

// Marsaglia & Tsang's constants for 256 layers (their Table 1).
Ziggurat make_normal() {
    return make_ziggurat(
        3.6541528853610088, 0.00492867323399, [](double x) { return std::exp(-0.5 * x * x); },
        [](double y) { return std::sqrt(-2.0 * std::log(y)); });
}

Ziggurat make_exponential() {
    return make_ziggurat(
        7.69711747013104972, 0.0039496598225815571993, [](double x) { return std::exp(-x); },
        [](double y) { return -std::log(y); });
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
