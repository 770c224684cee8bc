#include "minimize.h"

#include <algorithm>
#include <cmath>

namespace retroprism {

NmResult nelder_mead(const std::function<double(const std::vector<double>&)>& f,
                     std::vector<double> x0, double step, int maxEval) {
    const size_t n = x0.size();
    std::vector<std::vector<double>> s(n + 1, x0);
    for (size_t i = 0; i < n; ++i)
        s[i + 1][i] += step;
    std::vector<double> fs(n + 1);
    NmResult r;
    for (size_t i = 0; i <= n; ++i) {
        fs[i] = f(s[i]);
        r.evaluations++;
    }
    while (r.evaluations < maxEval) {
        std::vector<size_t> idx(n + 1);
        for (size_t i = 0; i <= n; ++i)
            idx[i] = i;
        std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return fs[a] < fs[b]; });
        const size_t best = idx[0], worst = idx[n], second = idx[n - 1];
        double size = 0;
        for (size_t i = 0; i <= n; ++i)
            for (size_t k = 0; k < n; ++k)
                size = std::max(size, std::abs(s[i][k] - s[best][k]));
        if (std::abs(fs[worst] - fs[best]) <= 1e-10 * std::abs(fs[best]) + 1e-15 && size < 1e-4)
            break;
        if (size < 1e-7) break;
        std::vector<double> centroid(n, 0.0);
        for (size_t i = 0; i <= n; ++i)
            if (i != worst)
                for (size_t k = 0; k < n; ++k)
                    centroid[k] += s[i][k] / double(n);
        auto along = [&](double t) {
            std::vector<double> p(n);
            for (size_t k = 0; k < n; ++k)
                p[k] = centroid[k] + t * (s[worst][k] - centroid[k]);
            return p;
        };
        const std::vector<double> xr = along(-1.0);
        const double fr = f(xr);
        r.evaluations++;
        if (fr < fs[best]) {
            const std::vector<double> xe = along(-2.0);
            const double fe = f(xe);
            r.evaluations++;
            if (fe < fr) {
                s[worst] = xe;
                fs[worst] = fe;
            } else {
                s[worst] = xr;
                fs[worst] = fr;
            }
        } else if (fr < fs[second]) {
            s[worst] = xr;
            fs[worst] = fr;
        } else {
            const bool outside = fr < fs[worst];
            const std::vector<double> xc = along(outside ? -0.5 : 0.5);
            const double fc = f(xc);
            r.evaluations++;
            if (fc < (outside ? fr : fs[worst])) {
                s[worst] = xc;
                fs[worst] = fc;
            } else {
                for (size_t i = 0; i <= n; ++i)
                    if (i != best) {
                        for (size_t k = 0; k < n; ++k)
                            s[i][k] = s[best][k] + 0.5 * (s[i][k] - s[best][k]);
                        fs[i] = f(s[i]);
                        r.evaluations++;
                    }
            }
        }
    }
    size_t b = 0;
    for (size_t i = 1; i <= n; ++i)
        if (fs[i] < fs[b]) b = i;
    r.x = s[b];
    r.f = fs[b];
    return r;
}

double box_value(const BoxVar& v, double u) {
    const double t = 1.0 / (1.0 + std::exp(-u));
    return v.log ? std::exp(std::log(v.lo) + t * (std::log(v.hi) - std::log(v.lo)))
                 : v.lo + t * (v.hi - v.lo);
}

double box_coordinate(const BoxVar& v, double x) {
    const double a = v.log ? std::log(v.lo) : v.lo, b = v.log ? std::log(v.hi) : v.hi;
    const double y = v.log ? std::log(std::max(x, 1e-300)) : x;
    const double t = std::clamp((y - a) / (b - a), 1e-3, 1.0 - 1e-3);
    return std::log(t / (1.0 - t));
}

std::vector<std::vector<double>> box_starts(const std::vector<BoxVar>& vars,
                                            const std::vector<double>& base) {
    const size_t n = vars.size();
    std::vector<double> centre(n);
    for (size_t k = 0; k < n; ++k)
        centre[k] = box_value(vars[k], 0.0);
    std::vector<std::vector<double>> starts = {base, centre};
    for (size_t k = 0; k < n; ++k)
        for (double side : {-2.0, 2.0}) {
            std::vector<double> s = centre;
            s[k] = box_value(vars[k], side);
            starts.push_back(s);
        }
    return starts;
}

NmResult search_box(const std::function<double(const std::vector<double>&)>& f,
                    const std::vector<BoxVar>& vars, const std::vector<std::vector<double>>& starts,
                    int maxEval, int restarts) {
    const size_t n = vars.size();
    std::vector<double> x(n);
    auto values = [&](const std::vector<double>& u) {
        for (size_t k = 0; k < n; ++k)
            x[k] = box_value(vars[k], u[k]);
        return x;
    };
    if (n == 0) {
        NmResult r;
        r.f = f({});
        r.evaluations = 1;
        return r;
    }
    auto g = [&](const std::vector<double>& u) { return f(values(u)); };
    NmResult best;
    int evals = 0;
    for (const std::vector<double>& s : starts) {
        std::vector<double> u(n);
        for (size_t k = 0; k < n; ++k)
            u[k] = box_coordinate(vars[k], s.at(k));
        const NmResult r = nelder_mead(g, u, 0.7, maxEval);
        evals += r.evaluations;
        if (r.f < best.f) best = r;
    }
    for (int restart = 0; restart < restarts && !best.x.empty(); ++restart) {
        const NmResult r = nelder_mead(g, best.x, 0.3, maxEval);
        evals += r.evaluations;
        const bool better = r.f < best.f * (1.0 - 1e-9);
        if (r.f < best.f) best = r;
        if (!better) break;
    }
    best.evaluations = evals;
    if (!best.x.empty()) best.x = values(best.x);
    return best;
}

} // namespace retroprism
