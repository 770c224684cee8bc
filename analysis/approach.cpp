#include "approach.h"

#include <cmath>

#include "photometry.h"

namespace retroprism {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;

double angle_deg(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) / kDeg;
}
} // namespace

std::vector<ApproachPoint> approach_luminance(const LobeBrdf& brdf, const ApproachSettings& s) {
    std::vector<ApproachPoint> out;
    const glm::dvec3 lamp(0.0), eye(0.0, s.eye_above_lamp, 0.0);
    // The sign's frame: normal toward the driver, tangent horizontal.
    const glm::dvec3 n(0, 0, -1), t(1, 0, 0), b = glm::cross(n, t);
    auto local = [&](const glm::dvec3& w) {
        return glm::dvec3(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n));
    };
    for (int k = 0; k < s.steps; ++k) {
        ApproachPoint p;
        p.distance = s.steps > 1 ? s.far_m + (s.near_m - s.far_m) * k / (s.steps - 1) : s.far_m;
        const glm::dvec3 sign(s.sign_right, s.sign_up, p.distance);
        const glm::dvec3 toLamp = lamp - sign, toEye = eye - sign;
        const double r2 = glm::dot(toLamp, toLamp);
        const glm::dvec3 wi = local(glm::normalize(toLamp)), wo = local(glm::normalize(toEye));
        glm::dvec3 lobes[3];
        brdf(wi, wo, lobes);
        const double f = luminance_709(lobes[0] + lobes[1] + lobes[2]);
        p.observation_deg = angle_deg(toLamp, toEye);
        p.entrance_deg = angle_deg(toLamp, n);
        p.ra = f * wi.z * wo.z;
        p.luminance = f * wi.z * s.lamp_cd / r2;
        out.push_back(p);
    }
    return out;
}

} // namespace retroprism
