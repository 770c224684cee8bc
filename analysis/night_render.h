// night_render.h: a night-time preview of a material with the C++ reference node
// (PrismaticRetroreflector<double>), direct lighting only: `retroprism render`.
//
// Scene (metres; camera at the origin looking down -z, +y up, pinhole):
//  - a diamond sign (a square of side 0.85 m turned 45 degrees in its plane, like a warning
//    sign), centre (-0.62, 0, -8), turned about the vertical so that the headlight's entrance
//    angle at its centre is signAngleDeg; its tangent (the prisms' reference azimuth, the datum
//    mark) is the sign's horizontal axis;
//  - a sphere of radius 0.5 m, centre (0.75, 0, -8.2); tangent along the parallels
//    (normalize(up x n)), so that oriented prisms show their azimuth dependence;
//  - a headlight: an isotropic point source below the eye, placed so that the observation angle
//    at the sign's centre is observationDeg (0.5 degrees: a car's low beam and driver at
//    ~70 m), intensity such that the illuminance perpendicular to it at the sign's centre is 1;
//  - with fill, a fill light: a point source up and to the left behind the camera, (-3, 4, 1),
//    giving an illuminance of 60 at the sign's centre (dusk), so the day colour shows.
// Shading: at each hit, wi (to the light) and wo (to the eye) in the surface's local frame
// (normal, tangent), the node's f per lobe times cos(theta_i) times the light's irradiance
// (I / d^2), with shadow rays; the material's normal and tangent inputs are not used.
// Pixels: spp^2 stratified sub-pixel rays, box filter.
#pragma once

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "baselines.h"
#include "prismatic_retroreflector.h"

namespace retroprism {

struct NightLight {
    glm::dvec3 position;
    double intensity; // radiant intensity, scene units per sr
};

struct NightSettings {
    int width = 960;
    int height = 540;
    int spp = 3;                 // spp x spp rays per pixel
    double observationDeg = 0.5; // at the sign's centre
    double signAngleDeg = 15;    // entrance angle of the headlight at the sign's centre
    bool fill = false;
};

// The scene's lights and the angles measured at the sign's centre (degrees).
struct NightSceneInfo {
    std::vector<NightLight> lights; // the headlight first
    double observationAtSign = 0;
    double entranceAtSign = 0;
};

struct NightImage {
    int width = 0, height = 0;
    // Per pixel, row 0 at the top: surface, retro, diffuse linear RGB (3 floats each), and the
    // coverage. A MaterialX material (backends/mx_night.h) has the node's lobes as they reach
    // the surface through its graph where the graph allows separating them (empty otherwise),
    // and in `other` the rest of its response (everything when the lobes are empty); `other` is
    // empty for the node alone. The radiance is the sum of the layers present.
    std::vector<float> surface, retro, diffuse, alpha;
    std::vector<float> other;
    NightSceneInfo scene;
    long anomalies = 0; // NaN, infinite or negative lobe values the BRDF returned (must be 0)
};

// A BRDF by lobe in the local shading frame (normal +z, tangent +x): lobes[0..2] = surface,
// retro, diffuse f(wi, wo) in 1/sr, without the cosine.
using LobeBrdf =
    std::function<void(const glm::dvec3& wi, const glm::dvec3& wo, glm::dvec3 lobes[3])>;
// The node built from `material` with its normal and tangent replaced by the default frame.
LobeBrdf node_lobes(const Params& material);
// The MaterialX-style retroreflective GGX: its GGX lobe as "retro", its base as "diffuse".
LobeBrdf mrm_lobes(const baselines::RetroreflectiveGGX& m);

// Renders `material` (its normal and tangent replaced by the default frame) in the scene above.
NightImage render_night(const Params& material, const NightSettings& settings);
// The same for any BRDF.
NightImage render_night(const LobeBrdf& brdf, const NightSettings& settings);

} // namespace retroprism
