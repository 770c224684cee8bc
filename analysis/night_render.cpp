#include "night_render.h"
#include "night_scene.h"

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

// The lobes' radiance through one pixel (spp x spp stratified rays, box filter) and its
// coverage; counts the BRDF's non-finite or negative values in `anomalies`.
void shade_pixel(const NightScene& scene, const LobeBrdf& brdf, const NightSettings& st, int x,
                 int y, dvec3 sum[3], int& hits, std::atomic<long>& anomalies) {
    const int spp = st.spp;
    for (int sy = 0; sy < spp; ++sy)
        for (int sx = 0; sx < spp; ++sx) {
            const double px = (x + (sx + 0.5) / spp) / st.width;
            const double py = (y + (sy + 0.5) / spp) / st.height;
            const dvec3 d = scene.ray(px, py);
            NightHit h;
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
    const NightScene scene = build_night_scene(st);
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
