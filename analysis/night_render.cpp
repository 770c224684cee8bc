#include "night_render.h"

#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>

#include "parallel.h"
#include "progress.h"

using glm::dvec3;

namespace retroprism {

namespace {

using Node = PrismaticRetroreflector<double>;
constexpr double kDeg = M_PI / 180.0;
constexpr double kHitEps = 1e-6;

struct Hit {
    double t = 1e300;
    dvec3 p{0}, n{0, 0, 1}, tangent{1, 0, 0};
    int object = -1;
};

struct Sign {
    dvec3 c, n, u, v; // centre, normal, in-plane horizontal (tangent) and vertical axes
    double halfDiagonal = 0;
    bool intersect(const dvec3& o, const dvec3& d, Hit& h) const {
        const double dn = glm::dot(d, n);
        if (std::abs(dn) < 1e-12) return false;
        const double t = glm::dot(c - o, n) / dn;
        if (!(t > kHitEps) || t >= h.t) return false;
        const dvec3 p = o + t * d;
        const double a = glm::dot(p - c, u), b = glm::dot(p - c, v);
        if (std::abs(a) + std::abs(b) > halfDiagonal) return false;
        h.t = t;
        h.p = p;
        h.n = n;
        h.tangent = u;
        h.object = 0;
        return true;
    }
};

struct Sphere {
    dvec3 c;
    double r = 0;
    bool intersect(const dvec3& o, const dvec3& d, Hit& h) const {
        const dvec3 oc = o - c;
        const double b = glm::dot(oc, d), cc = glm::dot(oc, oc) - r * r;
        const double disc = b * b - cc;
        if (disc < 0) return false;
        const double s = std::sqrt(disc);
        double t = -b - s;
        if (!(t > kHitEps)) t = -b + s;
        if (!(t > kHitEps) || t >= h.t) return false;
        h.t = t;
        h.p = o + t * d;
        h.n = glm::normalize(h.p - c);
        const dvec3 tg = glm::cross(dvec3(0, 1, 0), h.n);
        h.tangent = glm::length(tg) > 1e-9 ? glm::normalize(tg) : dvec3(1, 0, 0);
        h.object = 1;
        return true;
    }
};

struct Scene {
    dvec3 eye{0, 0, 0};
    double tanX = 0, tanY = 0; // half-extents of the image plane at distance 1
    Sign sign;
    Sphere sphere;
    std::vector<NightLight> lights;
    double observationAtSign = 0, entranceAtSign = 0; // degrees, measured

    bool trace(const dvec3& o, const dvec3& d, Hit& h) const {
        bool any = sign.intersect(o, d, h);
        any = sphere.intersect(o, d, h) || any;
        return any;
    }
    bool occluded(const dvec3& p, const dvec3& n, const dvec3& to) const {
        const dvec3 o = p + n * 1e-5;
        const dvec3 d = to - o;
        const double dist = glm::length(d);
        Hit h;
        h.t = dist * (1.0 - 1e-9);
        return trace(o, d / dist, h);
    }
};

double angle_deg(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) / kDeg;
}

Scene build_scene(int width, int height, double observationDeg, double signAngleDeg, bool fill) {
    Scene s;
    const double aspect = double(width) / double(height);
    // Frame at least 2.7 m x 1.6 m at 8 m.
    const double halfW = std::max(1.35, 0.8 * aspect) / 8.0;
    s.tanX = halfW;
    s.tanY = halfW / aspect;
    // The headlight below the eye: first placed for a sign facing the eye, refined below.
    const dvec3 signC(-0.62, 0.0, -8.0);
    const double D = glm::length(signC - s.eye);
    double h = D * std::tan(observationDeg * kDeg);
    dvec3 light = s.eye - dvec3(0, h, 0);
    for (int it = 0; it < 3 && observationDeg > 0; ++it) {
        const double a = angle_deg(light - signC, s.eye - signC);
        h *= observationDeg / a;
        light = s.eye - dvec3(0, h, 0);
    }
    // The sign turned about the vertical (away from the camera's side) by the entrance angle
    // relative to the direction to the light.
    const dvec3 toLight = glm::normalize(light - signC);
    const double yaw0 = std::atan2(toLight.x, toLight.z);
    const double yaw = yaw0 - signAngleDeg * kDeg;
    s.sign.c = signC;
    s.sign.n = dvec3(std::sin(yaw), 0.0, std::cos(yaw));
    s.sign.u = glm::normalize(glm::cross(dvec3(0, 1, 0), s.sign.n));
    s.sign.v = glm::cross(s.sign.n, s.sign.u);
    s.sign.halfDiagonal = 0.85 / std::sqrt(2.0);
    s.sphere.c = dvec3(0.75, 0.0, -8.2);
    s.sphere.r = 0.5;
    const double dl2 = glm::dot(light - signC, light - signC);
    s.lights.push_back({light, dl2}); // illuminance 1 at the sign's centre
    if (fill) {
        const dvec3 f(-3.0, 4.0, 1.0);
        s.lights.push_back({f, 60.0 * glm::dot(f - signC, f - signC)});
    }
    s.observationAtSign = angle_deg(light - signC, s.eye - signC);
    s.entranceAtSign = angle_deg(light - signC, s.sign.n);
    return s;
}

// The lobes' radiance through one pixel (spp x spp stratified rays, box filter) and its
// coverage; counts the BRDF's non-finite or negative values in `anomalies`.
void shade_pixel(const Scene& scene, const LobeBrdf& brdf, const NightSettings& st, int x, int y,
                 dvec3 sum[3], int& hits, std::atomic<long>& anomalies) {
    const int spp = st.spp;
    for (int sy = 0; sy < spp; ++sy)
        for (int sx = 0; sx < spp; ++sx) {
            const double px = (x + (sx + 0.5) / spp) / st.width;
            const double py = (y + (sy + 0.5) / spp) / st.height;
            const dvec3 d =
                glm::normalize(dvec3((2 * px - 1) * scene.tanX, (1 - 2 * py) * scene.tanY, -1.0));
            Hit h;
            if (!scene.trace(scene.eye, d, h)) continue;
            ++hits;
            const dvec3 t = h.tangent, b = glm::cross(h.n, h.tangent);
            auto local = [&](const dvec3& w) {
                return dvec3(glm::dot(w, t), glm::dot(w, b), glm::dot(w, h.n));
            };
            const dvec3 wo = local(-d);
            for (const NightLight& l : scene.lights) {
                const dvec3 toL = l.position - h.p;
                const double d2 = glm::dot(toL, toL);
                const dvec3 wi = local(toL / std::sqrt(d2));
                if (wi.z <= 0 || wo.z <= 0) continue;
                if (scene.occluded(h.p, h.n, l.position)) continue;
                dvec3 lobes[3];
                brdf(wi, wo, lobes);
                const double k = wi.z * l.intensity / d2;
                for (int j = 0; j < 3; ++j) {
                    for (int c = 0; c < 3; ++c)
                        if (!std::isfinite(lobes[j][c]) || lobes[j][c] < 0) ++anomalies;
                    sum[j] += lobes[j] * k;
                }
            }
        }
}

} // namespace

LobeBrdf node_lobes(const Params& material) {
    Params shading = material;
    shading.normal = {0.0, 0.0, 1.0};
    shading.tangent = {1.0, 0.0, 0.0};
    auto node = std::make_shared<const Node>(shading);
    return [node](const dvec3& wi, const dvec3& wo, dvec3 lobes[3]) {
        const Node::Lobes f = node->f(wi, wo);
        lobes[0] = f.surface;
        lobes[1] = f.retro;
        lobes[2] = f.diffuse;
    };
}

LobeBrdf mrm_lobes(const baselines::RetroreflectiveGGX& m) {
    return [m](const dvec3& wi, const dvec3& wo, dvec3 lobes[3]) {
        const auto parts = m.parts(wi, wo);
        lobes[0] = dvec3(0.0);
        lobes[1] = parts.specular;
        lobes[2] = parts.diffuse;
    };
}

NightImage render_night(const Params& material, const NightSettings& st) {
    return render_night(node_lobes(material), st);
}

NightImage render_night(const LobeBrdf& brdf, const NightSettings& st) {
    const Scene scene =
        build_scene(st.width, st.height, st.observationDeg, st.signAngleDeg, st.fill);
    NightImage img;
    img.width = st.width;
    img.height = st.height;
    img.scene = {scene.lights, scene.observationAtSign, scene.entranceAtSign};
    const size_t n = size_t(st.width) * size_t(st.height);
    img.surface.assign(3 * n, 0.0f);
    img.retro.assign(3 * n, 0.0f);
    img.diffuse.assign(3 * n, 0.0f);
    img.alpha.assign(n, 0.0f);
    std::atomic<long> anomalies{0};
    std::atomic<int> rowsDone{0};
    std::mutex progressMutex;
    ProgressBar progress("render", "rows");
    parallel_for(size_t(st.height), 0, [&](size_t yi) {
        const int y = int(yi);
        for (int x = 0; x < st.width; ++x) {
            dvec3 sum[3] = {dvec3(0), dvec3(0), dvec3(0)};
            int hits = 0;
            shade_pixel(scene, brdf, st, x, y, sum, hits, anomalies);
            const double inv = 1.0 / (st.spp * st.spp);
            const size_t i = size_t(y) * size_t(st.width) + size_t(x);
            for (int c = 0; c < 3; ++c) {
                img.surface[3 * i + size_t(c)] = float(sum[0][c] * inv);
                img.retro[3 * i + size_t(c)] = float(sum[1][c] * inv);
                img.diffuse[3 * i + size_t(c)] = float(sum[2][c] * inv);
            }
            img.alpha[i] = float(hits * inv);
        }
        const std::lock_guard<std::mutex> lock(progressMutex);
        progress(std::uint64_t(++rowsDone), std::uint64_t(st.height));
    });
    img.anomalies = anomalies;
    return img;
}

} // namespace retroprism
