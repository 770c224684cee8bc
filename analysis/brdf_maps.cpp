#include "brdf_maps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "parallel.h"
#include "photometry.h"

namespace retroprism {

namespace {

using Node = PrismaticRetroreflector<double>;
using vec3 = Node::vec3;
constexpr double kDeg = M_PI / 180.0;

vec3 incident(double thetaIDeg) {
    return vec3(std::sin(thetaIDeg * kDeg), 0.0, std::cos(thetaIDeg * kDeg));
}

} // namespace

void Anomalies::check(const Node::Lobes& f, const vec3& wi, const vec3& wo) {
    const vec3 v[3] = {f.surface, f.retro, f.diffuse};
    const char* names[3] = {"surface", "retro", "diffuse"};
    for (int l = 0; l < 3; ++l)
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(v[l][c]) || v[l][c] < 0) {
                if (++count == 1) {
                    char buf[256];
                    std::snprintf(buf, sizeof buf,
                                  "%s[%d] = %g at wi = (%.6f, %.6f, %.6f), wo = (%.6f, %.6f, %.6f)",
                                  names[l], c, v[l][c], wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
                    example = buf;
                }
            }
}

std::vector<float> hemisphere_maps(const Node& node, const std::vector<double>& thetaIDeg, int n,
                                   Anomalies& anomalies) {
    const int panels = int(thetaIDeg.size()), width = panels * n, nch = 12;
    std::vector<float> data(size_t(width) * n * nch, 0.0f);
    parallel_for(size_t(n), 0, [&](size_t yi) {
        const int y = int(yi);
        const double v = 1.0 - (y + 0.5) * 2.0 / n;
        for (int k = 0; k < panels; ++k) {
            const vec3 wi = incident(thetaIDeg[size_t(k)]);
            for (int x = 0; x < n; ++x) {
                const double u = (x + 0.5) * 2.0 / n - 1.0;
                const double r2 = u * u + v * v;
                if (r2 >= 1.0) continue;
                const vec3 wo(u, v, std::sqrt(1.0 - r2));
                const Node::Eval e = node.eval(wi, wo);
                anomalies.check(e.f, wi, wo);
                const vec3 lobes[4] = {e.f.surface, e.f.retro, e.f.diffuse, e.f.total()};
                float* px = &data[(size_t(y) * width + size_t(k) * n + x) * nch];
                for (int l = 0; l < 4; ++l)
                    for (int c = 0; c < 3; ++c)
                        px[3 * l + c] = float(lobes[l][c] * wo.z);
            }
        }
    });
    return data;
}

std::vector<double> slice_angles(double thetaIDeg, int uniformSamples) {
    std::vector<double> s;
    for (int i = 0; i <= uniformSamples; ++i)
        s.push_back(-90.0 + 180.0 * i / uniformSamples);
    for (double peak : {thetaIDeg, -thetaIDeg}) {
        s.push_back(peak);
        for (double d = 1e-4; d < 3.0; d *= 1.25) {
            s.push_back(peak - d);
            s.push_back(peak + d);
        }
    }
    std::sort(s.begin(), s.end());
    s.erase(std::remove_if(s.begin(), s.end(), [](double a) { return a < -90.0 || a > 90.0; }),
            s.end());
    s.erase(std::unique(s.begin(), s.end()), s.end());
    return s;
}

BrdfSlice brdf_slice(const Node& node, double thetaIDeg, int uniformSamples, Anomalies& anomalies) {
    BrdfSlice sl;
    sl.thetaIDeg = thetaIDeg;
    sl.s = slice_angles(thetaIDeg, uniformSamples);
    for (auto& v : sl.y)
        v.assign(sl.s.size(), 0.0);
    const vec3 wi = incident(thetaIDeg);
    parallel_for(sl.s.size(), 0, [&](size_t i) {
        const double a = sl.s[i] * kDeg;
        const vec3 wo(std::sin(a), 0.0, std::cos(a));
        const Node::Eval e = node.eval(wi, wo);
        anomalies.check(e.f, wi, wo);
        const double c = std::max(wo.z, 0.0);
        sl.y[0][i] = luminance_709(e.f.surface) * c;
        sl.y[1][i] = luminance_709(e.f.retro) * c;
        sl.y[2][i] = luminance_709(e.f.diffuse) * c;
        sl.y[3][i] = luminance_709(e.f.total()) * c;
    });
    return sl;
}

} // namespace retroprism
