#include "approach.h"

#include <cmath>

#include "error.h"
#include "parse.h"

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

const std::vector<Vehicle>& vehicle_presets() {
    static const std::vector<Vehicle> v = {
        {"car", 1.2, 0.60, 1.08, 0.37},
        {"suv", 1.5, 0.85, 1.60, 0.40},
        {"truck", 1.9, 1.10, 2.40, 0.55},
    };
    return v;
}

const Vehicle& vehicle_preset(const std::string& name) {
    for (const Vehicle& v : vehicle_presets())
        if (v.name == name) return v;
    throw InputError("--vehicle " + name + ": expected car, suv or truck");
}

SignPosition sign_position(const std::string& name) {
    if (name == "shoulder") return SignPosition::Shoulder;
    if (name == "overhead") return SignPosition::Overhead;
    throw InputError("--sign " + name + ": expected shoulder or overhead");
}

double default_sign_right(SignPosition p) {
    return p == SignPosition::Shoulder ? 5.5 : 0.0;
}

double default_sign_height(SignPosition p) {
    return p == SignPosition::Shoulder ? 2.1 : 6.1;
}

namespace {

// The sign's centre and frame at arc length d along the lane's middle.
struct SignFrame {
    glm::dvec3 centre, n, t;
};

SignFrame sign_frame(const HeadlampSettings& s, double d) {
    // The lane's middle: a circle through the origin, heading +z, centre (R, 0, 0).
    glm::dvec3 p(0.0, 0.0, d), ahead(0, 0, 1), right(1, 0, 0);
    if (s.curve_radius != 0) {
        const double R = s.curve_radius, th = d / R;
        p = glm::dvec3(R - R * std::cos(th), 0.0, R * std::sin(th));
        ahead = glm::dvec3(std::sin(th), 0.0, std::cos(th));
        right = glm::dvec3(std::cos(th), 0.0, -std::sin(th));
    }
    return {p + right * s.sign_right + glm::dvec3(0.0, s.sign_height, 0.0), -ahead, right};
}

LampAtSign lamp_at_sign(const LobeBrdf& brdf, const LuminousIntensityDistribution& lid,
                        const glm::dvec3& lamp, const glm::dvec3& eye, const SignFrame& sf) {
    const glm::dvec3 b = glm::cross(sf.n, sf.t);
    auto local = [&](const glm::dvec3& w) {
        return glm::dvec3(glm::dot(w, sf.t), glm::dot(w, b), glm::dot(w, sf.n));
    };
    const glm::dvec3 toLamp = lamp - sf.centre;
    const double r2 = glm::dot(toLamp, toLamp);
    const glm::dvec3 wi = local(glm::normalize(toLamp)),
                     wo = local(glm::normalize(eye - sf.centre));
    LampAtSign l;
    l.angles = ra_geometry(wi, wo);
    l.intensity = lid.intensity(-toLamp);
    l.illuminance = l.intensity / r2;
    if (wi.z <= 0 || wo.z <= 0) return l; // the sign's back to the lamp or the eye
    glm::dvec3 lobes[3];
    brdf(wi, wo, lobes);
    const double f = luminance_709(lobes[0] + lobes[1] + lobes[2]);
    l.ra = f * wi.z * wo.z;
    l.luminance = f * wi.z * l.illuminance;
    return l;
}

} // namespace

std::vector<HeadlampPoint> approach_headlamps(const LobeBrdf& brdf,
                                              const LuminousIntensityDistribution& left,
                                              const LuminousIntensityDistribution& right,
                                              const HeadlampSettings& s) {
    const double minRadius = s.far_m / (0.5 * 3.14159265358979323846);
    if (s.curve_radius != 0 && !(std::abs(s.curve_radius) >= minRadius))
        throw InputError("--curve-radius " + number_text(s.curve_radius) +
                         ": expected 0 (straight) or a radius of at least " +
                         number_text(minRadius) + " m (the road turning at most 90 degrees over " +
                         number_text(s.far_m) + " m)");
    const Vehicle& v = s.vehicle;
    const glm::dvec3 lamps[2] = {{-0.5 * v.lamp_spacing, v.lamp_height, 0.0},
                                 {0.5 * v.lamp_spacing, v.lamp_height, 0.0}};
    const glm::dvec3 eye(-v.eye_left, v.eye_height, 0.0);
    std::vector<HeadlampPoint> out;
    for (int k = 0; k < s.steps; ++k) {
        HeadlampPoint p;
        p.distance = s.steps > 1 ? s.far_m + (s.near_m - s.far_m) * k / (s.steps - 1) : s.far_m;
        const SignFrame sf = sign_frame(s, p.distance);
        p.lamps[0] = lamp_at_sign(brdf, left, lamps[0], eye, sf);
        p.lamps[1] = lamp_at_sign(brdf, right, lamps[1], eye, sf);
        p.luminance = p.lamps[0].luminance + p.lamps[1].luminance;
        const double e = p.lamps[0].illuminance + p.lamps[1].illuminance;
        const double cosO = glm::dot(glm::normalize(eye - sf.centre), sf.n);
        p.demand = s.demand_cd_m2;
        if (e > 0 && cosO > 0) {
            p.ra_supplied = p.luminance * cosO / e;
            p.ra_needed = s.demand_cd_m2 * cosO / e;
        }
        out.push_back(p);
    }
    return out;
}

std::vector<ApproachPoint> approach_points(const std::vector<HeadlampPoint>& points, bool demand) {
    std::vector<ApproachPoint> out;
    for (const HeadlampPoint& p : points) {
        ApproachPoint a;
        a.distance = p.distance;
        a.observation_deg = p.lamps[0].angles.observation;
        a.entrance_deg = p.lamps[0].angles.entrance;
        a.ra = demand ? p.ra_needed : p.ra_supplied;
        a.luminance = demand ? p.demand : p.luminance;
        out.push_back(a);
    }
    return out;
}

} // namespace retroprism
