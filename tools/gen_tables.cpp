// gen_tables: writes nodes/generated/prism_tables.inc, the tables of the model that every
// backend shares (C++ float and double, GLSL). Built against a bootstrap build of the node
// whose own tables are placeholders; it uses only the exact, oriented ERA.
//
//   retroprism_gen_tables OUT.inc
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "prismatic_retroreflector.h"

using namespace retroprism;

namespace {

const int kEraAvgN = 2049; // nodes over t = tan(theta_t) in [0, sqrt 2]
const int kHitsN = 513;    // metallized prisms' face hits: nodes over t in [0, sqrt 2]
const int kTirNt = 129;    // fast tier's table of the uncoated average: nodes over t
const int kTirNeta = 81;   // and over eta in [1, 3]
const int kFdrTerms = 16;  // F_dr series: Chebyshev terms over eta in [1, 3]
const double kFdrEtaMax = 3.0;
const double kTanMax = 1.41421356237309504880; // A = 0 beyond theta_t = 54.74 deg
const int kLambdaDegree = 6;   // the float backends' Lambda: P / (a Q), both of this degree
const double kLambdaCut = 3.7; // and 0 beyond: Lambda(3.7) = 6.3e-9, below float's 1 - G1

void write_table(FILE* f, const char* name, const std::vector<double>& v) {
    std::fprintf(f, "RP_TABLE_BEGIN(%s, %d)\n", name, int(v.size()));
    for (size_t i = 0; i < v.size(); ++i) {
        // Seventeen significant digits round-trip a double; a decimal point keeps every
        // literal a floating-point one in GLSL too.
        char num[32];
        std::snprintf(num, sizeof num, "%.17g", v[i]);
        std::string s = num;
        if (s.find_first_of(".e") == std::string::npos) s += ".0";
        std::fprintf(f, "%s%s", s.c_str(), i + 1 == v.size() ? "\n" : (i % 4 == 3 ? ",\n" : ", "));
    }
    std::fprintf(f, "RP_TABLE_END\n");
}

// Chebyshev coefficients c_j of S(eta) = F_dr_ext(eta) - g(eta) ln(eta - 1) (g:
// rp_fdr_log_weight) = sum_j c_j T_j(u), u = (eta - mid) / half mapping [1, kFdrEtaMax] to
// [-1, 1], from S at 128 Chebyshev points (discrete orthogonality: exact for the first terms of
// a series that has converged to rounding well before the 128th term).
std::vector<double> fdr_series() {
    const int m = 128;
    const double pi = 3.14159265358979323846;
    const double mid = 0.5 * (kFdrEtaMax + 1.0), half = 0.5 * (kFdrEtaMax - 1.0);
    std::vector<double> c(kFdrTerms, 0.0);
    for (int k = 0; k < m; ++k) {
        const double theta = pi * (k + 0.5) / m;
        const double eta = mid + half * std::cos(theta);
        const double s = fdr_external(eta) - f64::rp_fdr_log_weight(eta) * std::log(eta - 1.0);
        for (int j = 0; j < kFdrTerms; ++j)
            c[j] += 2.0 / m * s * std::cos(j * theta);
    }
    c[0] *= 0.5;
    return c;
}

// The least-squares solution of the m x n system `a` x = b (column-major, m >= n, full rank) by
// Householder reflections; a and b are overwritten.
std::vector<double> least_squares(std::vector<double>& a, std::vector<double>& b, int m, int n) {
    for (int k = 0; k < n; ++k) {
        double* col = &a[size_t(k) * m];
        double norm = 0.0;
        for (int i = k; i < m; ++i)
            norm += col[i] * col[i];
        norm = std::sqrt(norm);
        const double alpha = col[k] > 0 ? -norm : norm;
        std::vector<double> v(col + k, col + m);
        v[0] -= alpha;
        double vv = 0.0;
        for (double x : v)
            vv += x * x;
        if (vv == 0.0) continue;
        auto reflect = [&](double* y) {
            double dotv = 0.0;
            for (int i = k; i < m; ++i)
                dotv += v[size_t(i - k)] * y[i];
            const double scale = 2.0 * dotv / vv;
            for (int i = k; i < m; ++i)
                y[i] -= scale * v[size_t(i - k)];
        };
        for (int j = k; j < n; ++j)
            reflect(&a[size_t(j) * m]);
        reflect(b.data());
    }
    std::vector<double> x(size_t(n), 0.0);
    for (int k = n - 1; k >= 0; --k) {
        double r = b[size_t(k)];
        for (int j = k + 1; j < n; ++j)
            r -= a[size_t(j) * m + k] * x[size_t(j)];
        x[size_t(k)] = r / a[size_t(k) * m + k];
    }
    return x;
}

// The float backends' Smith Lambda of Beckmann (the exact tier's; the double node keeps the erfc
// form, f64::rp_beckmann_lambda_of_a): a Lambda(a) = P(a) / Q(a) on (0, kLambdaCut], P and Q of
// degree kLambdaDegree, Q(0) = 1, fitted to the weighted minimax error in G1 = 1 / (1 + Lambda),
// |P / Q - a Lambda| / (a + a Lambda), by Lawson's iteration over linearised least-squares fits
// (Loeb's: the residual P - a Lambda Q divided by the previous Q) at 2000 Chebyshev points, in
// x = a / kLambdaCut and converted to powers of a. Returns P's coefficients, then Q's (Q_0 = 1),
// lowest power first, and in `worst` the largest error in G1 at 100001 points.
std::vector<double> lambda_rational(double& worst) {
    const int n = kLambdaDegree, m = 2000, unknowns = 2 * n + 1;
    const size_t points = 2000;
    const double pi = 3.14159265358979323846;
    std::vector<double> x(points), g(points), w(points);
    for (int i = 0; i < m; ++i) {
        x[size_t(i)] = 0.5 * (1.0 - std::cos(pi * (i + 0.5) / m));
        const double a = kLambdaCut * x[size_t(i)];
        g[size_t(i)] = a * f64::rp_beckmann_lambda_of_a(a);
        w[size_t(i)] = 1.0 / (a + g[size_t(i)]);
    }
    auto horner = [](const double* c, int degree, double t) {
        double r = c[degree];
        for (int k = degree - 1; k >= 0; --k)
            r = r * t + c[k];
        return r;
    };
    std::vector<double> qPrev(points, 1.0), lawson(points, 1.0), best;
    double bestError = 1e300;
    for (int it = 0; it < 100; ++it) {
        std::vector<double> a(points * unknowns), b(points);
        for (int i = 0; i < m; ++i) {
            const double row = w[size_t(i)] * std::sqrt(lawson[size_t(i)]) / qPrev[size_t(i)];
            double power = 1.0;
            for (int k = 0; k <= n; ++k, power *= x[size_t(i)]) {
                a[size_t(k) * m + i] = row * power;
                if (k > 0) a[size_t(n + k) * m + i] = -row * g[size_t(i)] * power;
            }
            b[size_t(i)] = row * g[size_t(i)];
        }
        std::vector<double> c = least_squares(a, b, m, unknowns);
        std::vector<double> coef(c.begin(), c.begin() + n + 1);
        coef.push_back(1.0);
        coef.insert(coef.end(), c.begin() + n + 1, c.end());
        double error = 0.0, total = 0.0;
        std::vector<double> residual(points);
        for (int i = 0; i < m; ++i) {
            const double q = horner(&coef[size_t(n + 1)], n, x[size_t(i)]);
            const double r =
                w[size_t(i)] * (horner(coef.data(), n, x[size_t(i)]) / q - g[size_t(i)]);
            residual[size_t(i)] = std::abs(r);
            error = std::max(error, std::abs(r));
            qPrev[size_t(i)] = q;
        }
        if (error < bestError) {
            bestError = error;
            best = coef;
        }
        for (int i = 0; i < m; ++i) {
            lawson[size_t(i)] *= residual[size_t(i)];
            total += lawson[size_t(i)];
        }
        for (int i = 0; i < m; ++i)
            lawson[size_t(i)] = std::max(lawson[size_t(i)] * m / total, 1e-12);
    }
    // Powers of x = a / kLambdaCut to powers of a.
    double scale = 1.0;
    for (int k = 0; k <= n; ++k, scale /= kLambdaCut) {
        best[size_t(k)] *= scale;
        best[size_t(n + 1 + k)] *= scale;
    }
    worst = 0.0;
    for (int i = 1; i <= 100000; ++i) {
        const double a = kLambdaCut * i / 100000.0;
        const double g1 = 1.0 / (1.0 + f64::rp_beckmann_lambda_of_a(a));
        const double p = std::max(0.0, horner(best.data(), n, a));
        const double aq = a * horner(&best[size_t(n + 1)], n, a);
        worst = std::max(worst, std::abs(aq / (aq + p) - g1));
    }
    worst = std::max(worst, f64::rp_beckmann_lambda_of_a(kLambdaCut)); // cut off beyond
    return best;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: retroprism_gen_tables OUT.inc\n");
        return 2;
    }
    std::vector<double> era(kEraAvgN);
    for (int i = 0; i < kEraAvgN; ++i)
        era[i] = era_averaged_direct(kTanMax * i / (kEraAvgN - 1));
    std::vector<double> hits(kHitsN);
    for (int i = 0; i < kHitsN; ++i)
        hits[i] = metal_hits_averaged_direct(kTanMax * i / (kHitsN - 1));
    std::vector<double> tir(size_t(kTirNt) * kTirNeta);
    for (int j = 0; j < kTirNeta; ++j)
        for (int i = 0; i < kTirNt; ++i)
            tir[size_t(j) * kTirNt + i] = f64::rp_retro_fraction_averaged_exact(
                kTanMax * i / (kTirNt - 1), 1.0 + 2.0 * j / (kTirNeta - 1), true);
    const std::vector<double> fdr = fdr_series();
    double lambdaWorst = 0.0;
    const std::vector<double> lambda = lambda_rational(lambdaWorst);
    FILE* f = std::fopen(argv[1], "w");
    if (!f) {
        std::fprintf(stderr, "retroprism_gen_tables: cannot write %s\n", argv[1]);
        return 1;
    }
    std::fprintf(
        f, "// Generated by retroprism_gen_tables (tools/gen_tables.cpp): do not edit.\n"
           "// Shared by every backend; tests/nodes/test_physics.cpp checks the interpolated\n"
           "// values against direct integration and that regeneration changes nothing.\n"
           "//\n"
           "// rp_era_avg_table: azimuth average of the ERA A (exact polygon overlap,\n"
           "// integrated piecewise between its kinks by rp_retro_fraction_averaged_exact)\n"
           "// at t = tan(theta_t) = RP_ERA_TAN_MAX i / (RP_ERA_AVG_N - 1); A = 0 beyond\n"
           "// theta_t = 54.74 deg. Linear interpolation in it is within 1e-5 of the\n"
           "// exact average everywhere (measured maximum 5.3e-6, at the kink t = 1/sqrt2).\n");
    std::fprintf(f, "const real RP_ERA_TAN_MAX = real(1.41421356237309504880);\n");
    std::fprintf(f, "// @rp-if era_averaged\n");
    std::fprintf(f, "const int RP_ERA_AVG_N = %d;\n", kEraAvgN);
    write_table(f, "rp_era_avg_table", era);
    std::fprintf(f, "// @rp-endif\n");
    std::fprintf(
        f, "// rp_metal_hits_avg_table: azimuth average of the number of faces a ray meets in the\n"
           "// paper's cube, sum_k H_k (rp_azimuth_average, piecewise Gauss-Legendre between\n"
           "// its kinks), at t = RP_ERA_TAN_MAX i / (RP_METAL_HITS_N - 1): the substrate term of\n"
           "// metallized prisms.\n");
    std::fprintf(f, "// @rp-if diffuse&prism_metallized&era_averaged\n");
    std::fprintf(f, "const int RP_METAL_HITS_N = %d;\n", kHitsN);
    write_table(f, "rp_metal_hits_avg_table", hits);
    std::fprintf(f, "// @rp-endif\n");
    std::fprintf(
        f, "// rp_tir_avg_table: the fast tier's azimuth average of A R1 R2 R3 for uncoated\n"
           "// prisms (rp_retro_fraction_averaged_exact) at t as above with RP_TIR_NT nodes\n"
           "// and eta in [1, RP_TIR_ETA_MAX] with RP_TIR_NETA nodes; entry [j RP_TIR_NT + i].\n");
    std::fprintf(f, "// @rp-if era_averaged&prism_tir&fidelity_fast\n");
    std::fprintf(f, "const int RP_TIR_NT = %d;\n", kTirNt);
    std::fprintf(f, "const int RP_TIR_NETA = %d;\n", kTirNeta);
    std::fprintf(f, "const real RP_TIR_ETA_MAX = real(3.0);\n");
    write_table(f, "rp_tir_avg_table", tir);
    std::fprintf(f, "// @rp-endif\n");
    std::fprintf(
        f, "// rp_fdr_ext_series: F_dr_ext(eta), the outside hemispherical reflectance of the\n"
           "// top surface (exact: retroprism::fdr_external), for backends without double\n"
           "// precision (the C++ node computes it exactly), as S(eta) + g(eta) ln(eta - 1) on\n"
           "// eta in [1, RP_FDR_ETA_MAX]: g = eta^2 (eta^2 - 1)^2 / (eta^2 + 1)^3 is the closed\n"
           "// form's only term not analytic at eta = 1, and S = sum_j c_j T_j(u), the table's\n"
           "// RP_FDR_TERMS Chebyshev coefficients c_j of the analytic rest in u = (2 eta - 1 -\n"
           "// RP_FDR_ETA_MAX) / (RP_FDR_ETA_MAX - 1).\n");
    std::fprintf(f, "// @rp-if diffuse\n");
    std::fprintf(f, "const int RP_FDR_TERMS = %d;\n", kFdrTerms);
    std::fprintf(f, "const real RP_FDR_ETA_MAX = real(%.1f);\n", kFdrEtaMax);
    write_table(f, "rp_fdr_ext_series", fdr);
    std::fprintf(f, "// @rp-endif\n");
    std::fprintf(
        f,
        "// rp_lambda_rational: the exact tier's Smith Lambda of Beckmann in the float backends\n"
        "// (the double node keeps the erfc form) as a Lambda(a) = P(a) / Q(a) on\n"
        "// (0, RP_LAMBDA_RATIONAL_CUT], 0 beyond: P's RP_LAMBDA_DEGREE + 1 coefficients, then\n"
        "// Q's (Q(0) = 1), lowest power of a first; the weighted minimax fit of the error in\n"
        "// G1 = 1 / (1 + Lambda), largest %.1e over 1e5 points (cut-off included).\n",
        lambdaWorst);
    std::fprintf(f, "// @rp-if fidelity_exact\n");
    std::fprintf(f, "const int RP_LAMBDA_DEGREE = %d;\n", kLambdaDegree);
    std::fprintf(f, "const real RP_LAMBDA_RATIONAL_CUT = real(%.1f);\n", kLambdaCut);
    write_table(f, "rp_lambda_rational", lambda);
    std::fprintf(f, "// @rp-endif\n");
    std::fclose(f);
    return 0;
}
