// night_scene.h: the night preview's scene (night_render.h describes it), shared by the C++
// reference renderer (night_render.cpp) and the renderer of MaterialX's own shaders
// (backends/mx_night.h), so that both draw the same sign, sphere, camera and lights.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "night_render.h"

namespace retroprism {

struct NightHit {
    double t = 1e300;
    glm::dvec3 p{0}, n{0, 0, 1}, tangent{1, 0, 0};
    int object = -1; // kNightSign or kNightSphere
};

inline constexpr int kNightSign = 0;
inline constexpr int kNightSphere = 1;

// The diamond: centre c, normal n, in-plane horizontal (tangent) axis u and vertical axis v; a
// point p is on it when |(p - c).u| + |(p - c).v| <= halfDiagonal.
struct NightSign {
    glm::dvec3 c, n, u, v;
    double halfDiagonal = 0;
    bool intersect(const glm::dvec3& o, const glm::dvec3& d, NightHit& h) const;
};

// Tangent along the parallels, normalize(up x n).
struct NightSphere {
    glm::dvec3 c;
    double r = 0;
    bool intersect(const glm::dvec3& o, const glm::dvec3& d, NightHit& h) const;
};

struct NightScene {
    glm::dvec3 eye{0, 0, 0};   // looking down -z, +y up
    double tanX = 0, tanY = 0; // half-extents of the image plane at distance 1
    NightSign sign;
    NightSphere sphere;
    std::vector<NightLight> lights;                   // the headlight first
    double observationAtSign = 0, entranceAtSign = 0; // degrees, measured

    // The nearest hit along the ray o + t d (d unit), t in (1e-6, h.t).
    bool trace(const glm::dvec3& o, const glm::dvec3& d, NightHit& h) const;
    // Whether something lies between the surface point p (normal n) and the point `to`.
    bool occluded(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& to) const;
    // The unit direction from the eye through the image point (px, py) in [0, 1]^2 (row 0 at
    // the top).
    glm::dvec3 ray(double px, double py) const;
};

NightScene build_night_scene(const NightSettings& settings);

} // namespace retroprism
