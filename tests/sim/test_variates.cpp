// test_variates.cpp: the simulator's random variates and Smith Lambda (sim/variates.h): the
// ziggurats' layers (equal areas, and the share of draws accepted at once), the ziggurat normal
// and exponential variates against their distributions (chi-square, with the tails beyond the
// ziggurats' base layers in cells of their own), the Lambda table against the core's Lambda
// within its stated bound. Every TEST_CASE is tagged [sim].
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include <catch2/catch.hpp>

#include "prism_core.h"
#include "test_support.h"
#include "variates.h"

namespace sim = retroprism::sim;
namespace f64 = retroprism::f64;

namespace {

// Chi-square of `samples` draws against the CDF `cdf`, over cells with the given inner edges
// (plus the two unbounded end cells); returns its survival probability.
double chi2_p(const std::function<double(retroprism::Rng&)>& draw,
              const std::function<double(double)>& cdf, const std::vector<double>& edges,
              int samples, std::uint64_t seed, double& chi2) {
    std::vector<double> count(edges.size() + 1, 0.0);
    retroprism::Rng rng(seed, 0);
    for (int k = 0; k < samples; ++k) {
        const double x = draw(rng);
        count[size_t(std::upper_bound(edges.begin(), edges.end(), x) - edges.begin())] += 1;
    }
    chi2 = 0;
    for (size_t c = 0; c < count.size(); ++c) {
        const double lo = c == 0 ? 0.0 : cdf(edges[c - 1]);
        const double hi = c == edges.size() ? 1.0 : cdf(edges[c]);
        const double expected = samples * (hi - lo);
        chi2 += (count[c] - expected) * (count[c] - expected) / expected;
    }
    return rptest::chi2_sf(chi2, double(count.size() - 1));
}

// The tail start R of the n-layer ziggurat of density f (decreasing, f(0) = 1): the root of the
// top layer's closure x[n - 1] (1 - f(x[n - 1])) = v, v = R f(R) + tail(R), by bisection in long
// double (a larger R makes the layers thinner and the top one wider; too small an R reaches
// f = 1 before the top).
template <class F, class FInverse, class Tail>
long double ziggurat_r(int n, F f, FInverse fInverse, Tail tail) {
    const auto closure = [&](long double r) {
        const long double v = r * f(r) + tail(r);
        long double x = r;
        for (int i = 1; i < n - 1; ++i) {
            const long double y = f(x) + v / x;
            if (!(y < 1)) return -v;
            x = fInverse(y);
        }
        return x * (1 - f(x)) - v;
    };
    long double lo = 1, hi = 20;
    while (hi - lo > 1e-17L * hi)
        (closure(0.5L * (lo + hi)) < 0 ? lo : hi) = 0.5L * (lo + hi);
    return hi;
}

} // namespace

TEST_CASE("The ziggurats' tail starts are the roots of their top layers' closure", "[sim]") {
    // sim/variates.cpp writes R for its 1024 layers; the same bisection gives Marsaglia & Tsang's
    // R for 256 layers (their Table 1), so it checks itself too. Bound: a few ulps of R.
    const long double pi = 3.141592653589793238462643383279502884L;
    const auto normal = [](long double x) { return std::exp(-0.5L * x * x); };
    const auto normalInverse = [](long double y) { return std::sqrt(-2.0L * std::log(y)); };
    const auto normalTail = [pi](long double r) {
        return std::sqrt(0.5L * pi) * std::erfc(r / std::sqrt(2.0L));
    };
    const auto exponential = [](long double x) { return std::exp(-x); };
    const auto exponentialInverse = [](long double y) { return -std::log(y); };
    const auto exponentialTail = [](long double r) { return std::exp(-r); };
    const auto near = [](long double a, double b) { return std::abs(double(a) / b - 1) < 1e-15; };
    CHECK(near(ziggurat_r(256, normal, normalInverse, normalTail), 3.6541528853610088));
    CHECK(near(ziggurat_r(256, exponential, exponentialInverse, exponentialTail),
               7.69711747013104972));
    CHECK(near(ziggurat_r(sim::kZigguratLayers, normal, normalInverse, normalTail),
               sim::kZigguratNormal.r));
    CHECK(near(ziggurat_r(sim::kZigguratLayers, exponential, exponentialInverse, exponentialTail),
               sim::kZigguratExponential.r));
}

TEST_CASE("The ziggurats' layers have equal areas", "[sim]") {
    // Each layer i >= 1 is the rectangle [0, x_i] x [f(x_i), f(x_(i+1))] of area v, the base
    // layer R f(R) plus the tail beyond R, the top one [0, x_(N-1)] x [f(x_(N-1)), 1]; a first
    // try in layer i is accepted with probability x_(i+1) / x_i. The areas are computed in double
    // from the tables' doubles: relative deviations of a few 1e-13 are the rounding of the
    // tables (x_i to 1.1e-16, f(x_i) - f(x_(i+1)) near the top losing digits to cancellation).
    const auto check = [](const sim::Ziggurat& z, double tail, const char* name) {
        const int n = sim::kZigguratLayers;
        double worst = std::abs((z.r * z.f[0] + tail) / z.v - 1.0);
        double accept = 0;
        for (int i = 0; i < n; ++i) {
            const double top = i == n - 1 ? 1.0 : z.f[i + 1];
            if (i >= 1) worst = std::max(worst, std::abs(z.x[i] * (top - z.f[i]) / z.v - 1.0));
            accept += z.x[i + 1] / z.x[i] / n;
        }
        CHECK(worst < 1e-11);
        std::printf("MEASURED: %s ziggurat, %d layers: R %.6f, layer areas within %.1e of v, "
                    "%.2f%% of first tries accepted\n",
                    name, n, z.r, worst, 100 * accept);
        return accept;
    };
    const sim::Ziggurat& normal = sim::kZigguratNormal;
    const sim::Ziggurat& exponential = sim::kZigguratExponential;
    const double normalTail = std::sqrt(0.5 * M_PI) * std::erfc(normal.r / std::sqrt(2.0));
    CHECK(check(normal, normalTail, "normal") > 0.9955);
    CHECK(check(exponential, std::exp(-exponential.r), "exponential") > 0.9935);
}

TEST_CASE("Ziggurat variates follow the normal and exponential distributions", "[sim]") {
    // 4e6 draws each, cells of width 0.1 (normal: [-4.5, 4.5], the tails beyond R = 4.039 that
    // the base layer samples in 5 cells a side; exponential: [0, 10], and 10.. 13 beyond its
    // R = 9.256 in 0.5 cells): the chi-square's probability above 1e-4 each (fixed seeds: a
    // failure is a fault of the sampler, at 1e-4 significance).
    const int samples = 4000000;
    std::vector<double> edges;
    for (int i = -45; i <= 45; ++i)
        edges.push_back(0.1 * i);
    double chiNormal = 0;
    const double pNormal = chi2_p([](retroprism::Rng& r) { return sim::normal_variate(r); },
                                  [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); },
                                  edges, samples, 3, chiNormal);
    CHECK(pNormal > 1e-4);
    edges.clear();
    for (int i = 1; i <= 100; ++i)
        edges.push_back(0.1 * i);
    for (int i = 1; i <= 6; ++i)
        edges.push_back(10.0 + 0.5 * i);
    double chiExp = 0;
    const double pExp =
        chi2_p([](retroprism::Rng& r) { return sim::exponential_variate(r); },
               [](double x) { return x > 0 ? -std::expm1(-x) : 0.0; }, edges, samples, 4, chiExp);
    CHECK(pExp > 1e-4);
    std::printf("MEASURED: ziggurat variates, 4e6 draws: normal chi-square %.1f (91 dof, p %.3f), "
                "exponential %.1f (106 dof, p %.3f)\n",
                chiNormal, pNormal, chiExp, pExp);
}

TEST_CASE("The simulator's Lambda table is within its bound of the core's Lambda", "[sim]") {
    // 64 points per interval of the table (the interpolation error is smooth between its nodes)
    // and the ends of the range; beyond the cut both are 0.
    double worst = 0, worstA = 0;
    const int n = sim::kLambdaPieces * 64;
    for (int k = 0; k <= n; ++k) {
        const double a = std::max(1e-6, sim::kLambdaCut * k / n);
        const double exact = f64::rp_beckmann_lambda_of_a(a);
        const double rel = std::abs(sim::beckmann_lambda_table(a) / exact - 1.0);
        if (rel > worst) {
            worst = rel;
            worstA = a;
        }
    }
    CHECK(worst <= sim::kLambdaMaxRelError);
    CHECK(sim::beckmann_lambda_table(std::nextafter(sim::kLambdaCut, 10.0)) == 0.0);
    CHECK(f64::rp_beckmann_lambda_of_a(std::nextafter(sim::kLambdaCut, 10.0)) == 0.0);
    std::printf("MEASURED: Lambda table: largest relative error %.2g (at a = %.3f; bound %.0e)\n",
                worst, worstA, sim::kLambdaMaxRelError);
}
