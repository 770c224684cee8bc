// ra_render.h: the coefficient of retroreflection R_A of a shader measured as a renderer
// measures it: a direct-lighting render of a flat sample lit by a point source beside a pinhole
// camera, in the coplanar geometry of analysis/photometry.h (source at entrance angle beta from
// the sample's normal, camera at observation angle alpha from the source, on the source's side
// turned away from the normal: wo = (sin(beta - alpha), 0, cos(beta - alpha))).
//
// The sample is the plane z = 0 (normal +z, tangent dPdu = +x), untransformed and larger than the
// image (no pixel sees an edge); the source and the camera are at `distance` from its centre,
// the camera looking at it with a square image of `pixels` x `pixels` whose field is `window`
// metres wide at that distance. Each pixel's ray is shaded where it meets the sample: the closure's
// retroprism_bsdf components (RetroprismBsdf, with their weights) at view -I and light toward the
// source give the radiance L = f cos(theta_light) I_source / r^2. R_A = I / (E_perp A), the
// sample's intensity toward the camera per illuminance on a plane perpendicular to the source's
// direction at the centre (E_perp = I_source / distance^2) per area: the area-weighted mean of
// L cos(theta_view) / E_perp over the pixels' footprints (pixel solid angle times r^2 over
// cos(theta_view)).
#pragma once

#include <glm/glm.hpp>

#include "shading.h"

namespace retroprism::osl {

struct RaScene {
    double distance = 100.0; // metres, source and camera from the sample's centre
    double window = 0.1;     // metres of the sample the image spans
    int pixels = 24;
};

// R_A per RGB channel (cd lx^-1 m^-2) of the group's closure at entrance and observation angles
// in degrees.
glm::dvec3 render_ra(ShaderRunner& runner, const ShaderRunner::Group& group, double entranceDeg,
                     double observationDeg, const RaScene& scene = RaScene());

} // namespace retroprism::osl
