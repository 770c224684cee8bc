// approach.h: the luminance of a sign for a driver approaching it at night under low beams:
// `retroprism approach`.
//
// Scene (metres): the road along +z; one headlamp at the origin, the driver's eye
// `eye_above_lamp` straight above it; the sign's centre `sign_right` to the right of the lamp
// and `sign_up` above it, at distance d along the road, facing the driver (normal -z, tangent
// +x, the prisms' datum mark horizontal). The observation angle at the sign is the angle
// between the directions to the lamp and to the eye, about eye_above_lamp / d; the entrance
// angle is that between the direction to the lamp and the sign's normal.
// Sign luminance (cd m^-2, Rec. 709 Y): L = f(wi, wo) cos(theta_i) I / r^2, I the lamp's
// intensity toward the sign (cd), r its distance; equivalently R_A(alpha, beta) E_perp /
// cos(theta_o) with E_perp = I / r^2.
#pragma once

#include <vector>

#include "night_render.h"

namespace retroprism {

struct ApproachSettings {
    // ASTM E1710 / EN 1436 30 m geometry: headlamp 0.65 m, driver's eye 1.2 m above the road
    // (observation angle 1.05 degrees at 30 m).
    double eye_above_lamp = 0.55;
    double sign_right = 3.7; // m
    double sign_up = 1.5;    // m
    double lamp_cd = 1000;   // the lamp's intensity toward the sign
    double near_m = 30, far_m = 300;
    int steps = 91; // distances, evenly spaced from far to near
};

struct ApproachPoint {
    double distance = 0;        // m, along the road
    double observation_deg = 0; // at the sign's centre
    double entrance_deg = 0;
    double ra = 0;        // R_A at that geometry, cd lx^-1 m^-2
    double luminance = 0; // cd m^-2
};

std::vector<ApproachPoint> approach_luminance(const LobeBrdf& brdf, const ApproachSettings& s);

} // namespace retroprism
