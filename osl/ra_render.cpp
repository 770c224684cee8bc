#include "ra_render.h"

#include <cmath>

#include "retroprism_closure.h"

namespace retroprism::osl {

namespace {

OSL::Vec3 to_osl(const glm::dvec3& v) {
    return OSL::Vec3(float(v.x), float(v.y), float(v.z));
}

// The radiance toward the camera at one point of the sample (per unit source intensity): the
// retroprism_bsdf components of its closure, each with its weight.
glm::dvec3 radiance(const std::vector<Component>& closure, const glm::dvec3& P,
                    const glm::dvec3& source, const glm::dvec3& camera) {
    const glm::dvec3 toSource = source - P;
    const double r2 = glm::dot(toSource, toSource);
    const glm::dvec3 light = toSource / std::sqrt(r2);
    const glm::dvec3 view = glm::normalize(camera - P);
    glm::dvec3 L(0.0);
    for (const Component& c : closure) {
        if (c.id != kRetroprismClosureId) continue;
        const RetroprismBsdf bsdf(*static_cast<const ClosureParams*>(c.params));
        const OSL::Color3 f = bsdf.eval(to_osl(view), to_osl(light)).f;
        L += glm::dvec3(c.weight.x * f.x, c.weight.y * f.y, c.weight.z * f.z) *
             std::max(light.z, 0.0) / r2;
    }
    return L;
}

} // namespace

glm::dvec3 render_ra(ShaderRunner& runner, const ShaderRunner::Group& group, double entranceDeg,
                     double observationDeg, const RaScene& scene) {
    const double beta = glm::radians(entranceDeg);
    const double obs = glm::radians(observationDeg);
    const glm::dvec3 source = scene.distance * glm::dvec3(std::sin(beta), 0.0, std::cos(beta));
    const glm::dvec3 camera =
        scene.distance * glm::dvec3(std::sin(beta - obs), 0.0, std::cos(beta - obs));
    // The camera's frame: forward toward the centre, right along +y x forward.
    const glm::dvec3 forward = glm::normalize(-camera);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0.0, 1.0, 0.0)));
    const glm::dvec3 up = glm::cross(right, forward);
    // Image plane at distance 1: half-width so that the image spans the window where the
    // sample is nearest (its foreshortened width is smaller: the image stays inside).
    const double half = 0.5 * scene.window / scene.distance;
    const double pixel = 2.0 * half / scene.pixels;
    const double ePerp = 1.0 / (scene.distance * scene.distance); // unit source intensity
    glm::dvec3 weighted(0.0);
    double area = 0.0;
    for (int j = 0; j < scene.pixels; ++j) {
        for (int i = 0; i < scene.pixels; ++i) {
            const double x = -half + (i + 0.5) * pixel, y = -half + (j + 0.5) * pixel;
            const glm::dvec3 d = glm::normalize(forward + x * right + y * up);
            if (!(d.z < 0.0)) continue;
            const double t = -camera.z / d.z;
            const glm::dvec3 P = camera + t * d;
            ShadingPoint point;
            point.P = to_osl(P);
            point.I = to_osl(d);
            const std::vector<Component> closure = runner.shade(group, point);
            // The pixel's solid angle (image plane at distance 1) and its footprint on the plane.
            const double cosCam = glm::dot(d, forward);
            const double solidAngle = pixel * pixel * cosCam * cosCam * cosCam;
            const double cosView = -d.z;
            const double footprint = solidAngle * t * t / cosView;
            weighted += radiance(closure, P, source, camera) * cosView * footprint;
            area += footprint;
        }
    }
    return area > 0.0 ? weighted / (area * ePerp) : glm::dvec3(0.0);
}

} // namespace retroprism::osl
