// cube_corner.cpp: canted cube corners in the simulator (see cube_corner.h).
#include "cube_corner.h"

#include <cmath>
#include <limits>

namespace retroprism {
namespace sim {

CubeCorner canted_cube_corner(double cantDeg, double psi) {
    const double cant = cantDeg * (3.14159265358979323846 / 180.0);
    const dvec3 a = glm::normalize(dvec3(1.0, 1.0, 1.0));
    const dvec3 u = glm::normalize(dvec3(2.0, -1.0, -1.0));
    const dvec3 n = glm::normalize(a * std::cos(cant) + u * std::sin(cant));
    // The sheet's frame in the cube's: x toward e_1's projection, z = n.
    const dvec3 x = glm::normalize(dvec3(1.0, 0.0, 0.0) - n.x * n);
    const dvec3 y = glm::cross(n, x);
    const double c = std::cos(psi), s = std::sin(psi);
    CubeCorner cc;
    for (int k = 0; k < 3; ++k) {
        dvec3 axis(0.0);
        axis[k] = 1.0;
        const double ex = glm::dot(axis, x), ey = glm::dot(axis, y);
        cc.e[k] = dvec3(c * ex - s * ey, s * ex + c * ey, glm::dot(axis, n));
    }
    return cc;
}

PrismOutcome trace_cube_corner(const Sheet& sheet, const CubeCorner& cc, const dvec3& d0,
                               Rng& rng) {
    if (!(d0.z < 0)) return kPrismMiss;
    // Uniform entry point: barycentric weights of the aperture's vertices e_k / e_k.z.
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
    }
    dvec3 x = u * cc.e[0] / cc.e[0].z + v * cc.e[1] / cc.e[1].z +
              std::max(0.0, 1.0 - u - v) * cc.e[2] / cc.e[2].z;
    dvec3 d = d0;
    int reflections = 0;
    while (reflections < 4) {
        // Inside the convex solid the nearest plane ahead is where the ray meets its boundary:
        // the aperture z = 1 (upward rays) or a face.
        int face = -1;
        double tHit =
            d.z > 0 ? std::max(0.0, 1.0 - x.z) / d.z : std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
            const double toward = glm::dot(d, cc.e[k]);
            const double tk = toward < 0 ? std::max(0.0, glm::dot(x, cc.e[k])) / -toward
                                         : std::numeric_limits<double>::infinity();
            if (tk < tHit) {
                tHit = tk;
                face = k;
            }
        }
        if (face < 0) break; // through the aperture (or nowhere to go)
        x += tHit * d;
        x -= glm::dot(x, cc.e[face]) * cc.e[face]; // on the face plane
        const double cosK = -glm::dot(d, cc.e[face]);
        const bool tir = sheet.prism_reflection == f64::RP_PRISM_TIR;
        const double reflectance =
            tir ? f64::rp_fresnel_internal(cosK, sheet.eta)
                : (sheet.prism_reflection == f64::RP_PRISM_METALLIZED ? sheet.metal_reflectance
                                                                      : 1.0);
        if (reflectance < 1.0 && rng.uniform() >= reflectance)
            return tir ? kPrismTransmitted : kPrismAbsorbed;
        d += 2.0 * cosK * cc.e[face];
        ++reflections;
    }
    return reflections == 3 ? kPrismRetro : kPrismMiss;
}

} // namespace sim
} // namespace retroprism
