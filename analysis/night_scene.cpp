#include "night_scene.h"

#include <algorithm>
#include <cmath>

using glm::dvec3;

namespace retroprism {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kHitEps = 1e-6;

} // namespace

bool NightSign::intersect(const dvec3& o, const dvec3& d, NightHit& h) const {
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
    h.object = kNightSign;
    return true;
}

bool NightSphere::intersect(const dvec3& o, const dvec3& d, NightHit& h) const {
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
    h.object = kNightSphere;
    return true;
}

bool NightScene::trace(const dvec3& o, const dvec3& d, NightHit& h) const {
    bool any = sign.intersect(o, d, h);
    any = sphere.intersect(o, d, h) || any;
    return any;
}

bool NightScene::occluded(const dvec3& p, const dvec3& n, const dvec3& to) const {
    const dvec3 o = p + n * 1e-5;
    const dvec3 d = to - o;
    const double dist = glm::length(d);
    NightHit h;
    h.t = dist * (1.0 - 1e-9);
    return trace(o, d / dist, h);
}

dvec3 NightScene::ray(double px, double py) const {
    return glm::normalize(dvec3((2 * px - 1) * tanX, (1 - 2 * py) * tanY, -1.0));
}

namespace {

double angle_deg(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) / kDeg;
}

} // namespace

NightScene build_night_scene(const NightSettings& settings) {
    NightScene s;
    const double aspect = double(settings.width) / double(settings.height);
    const double observationDeg = settings.observationDeg;
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
    const double yaw = yaw0 - settings.signAngleDeg * kDeg;
    s.sign.c = signC;
    s.sign.n = dvec3(std::sin(yaw), 0.0, std::cos(yaw));
    s.sign.u = glm::normalize(glm::cross(dvec3(0, 1, 0), s.sign.n));
    s.sign.v = glm::cross(s.sign.n, s.sign.u);
    s.sign.halfDiagonal = 0.85 / std::sqrt(2.0);
    s.sphere.c = dvec3(0.75, 0.0, -8.2);
    s.sphere.r = 0.5;
    const double dl2 = glm::dot(light - signC, light - signC);
    s.lights.push_back({light, dl2}); // illuminance 1 at the sign's centre
    if (settings.fill) {
        const dvec3 f(-3.0, 4.0, 1.0);
        s.lights.push_back({f, 60.0 * glm::dot(f - signC, f - signC)});
    }
    s.observationAtSign = angle_deg(light - signC, s.eye - signC);
    s.entranceAtSign = angle_deg(light - signC, s.sign.n);
    return s;
}

} // namespace retroprism
