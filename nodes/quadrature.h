// quadrature.h: adaptive Gauss-Kronrod (7/15) integration in double, for the model's
// tabulated constants and the tests that check them. Not part of the shading path.
#pragma once

#include <cmath>
#include <vector>

namespace retroprism {

// One Gauss-Kronrod 7/15 panel over [a, b] (15 evaluations of f): the Kronrod estimate and
// the embedded 7-point Gauss one; |kronrod - gauss| estimates the panel's error.
struct GkPanel {
    double kronrod = 0;
    double gauss = 0;
};
template <class F>
GkPanel gauss_kronrod_15(const F& f, double a, double b) {
    static const double xk[8] = {0.991455371120812639, 0.949107912342758525, 0.864864423359769073,
                                 0.741531185599394440, 0.586087235467691130, 0.405845151377397167,
                                 0.207784955007898468, 0.000000000000000000};
    static const double wk[8] = {0.022935322010529225, 0.063092092629978553, 0.104790010322250184,
                                 0.140653259715525919, 0.169004726639267903, 0.190350578064785410,
                                 0.204432940075298892, 0.209482141084727828};
    static const double wg[4] = {0.129484966168869693, 0.279705391489276668, 0.381830050505118945,
                                 0.417959183673469388};
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    const double fc = f(c);
    double k = wk[7] * fc, g = wg[3] * fc;
    for (int j = 0; j < 7; ++j) {
        const double f1 = f(c - h * xk[j]), f2 = f(c + h * xk[j]);
        k += wk[j] * (f1 + f2);
        if (j % 2 == 1) g += wg[j / 2] * (f1 + f2);
    }
    return {k * h, g * h};
}

// Integrates f over [a, b] to an absolute error estimate below tol: each interval whose
// |K15 - G7| exceeds its share of tol is halved, down to max_depth levels.
template <class F>
double integrate_adaptive(const F& f, double a, double b, double tol = 1e-12, int max_depth = 30) {
    struct Rec {
        const F& f;
        int maxd;
        double run(double lo, double hi, double tol, int depth) const {
            const GkPanel p = gauss_kronrod_15(f, lo, hi);
            if (std::abs(p.kronrod - p.gauss) <= tol || depth >= maxd) return p.kronrod;
            const double c = 0.5 * (lo + hi);
            return run(lo, c, 0.5 * tol, depth + 1) + run(c, hi, 0.5 * tol, depth + 1);
        }
    };
    Rec r{f, max_depth};
    return r.run(a, b, tol, 0);
}

// Gauss-Legendre nodes x and weights w of the n-point rule on [-1, 1], n >= 1 (Newton's
// iteration on the Legendre polynomials' three-term recurrence, Abramowitz & Stegun 22.7.10,
// from the initial guess cos(pi (i + 3/4) / (n + 1/2)); weights by A&S 25.4.29).
inline void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(n, 0.0);
    w.assign(n, 0.0);
    for (int i = 0; i < (n + 1) / 2; ++i) {
        double z = std::cos(3.14159265358979323846 * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = w[n - 1 - i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}

} // namespace retroprism
