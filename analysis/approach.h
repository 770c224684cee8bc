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
//
// Two headlamps from photometric files (approach_headlamps): the same road frame, now with
// its origin on the road surface under the middle of the vehicle (the middle of its lane):
// +z ahead along the road, +y up, +x to the right. The lamps stand lamp_spacing apart at
// lamp_height, their distributions (io/luminaire.h) in this frame (aimed straight ahead; the
// aim's tilt is in the file); the driver's eye eye_left to the left of the middle at
// eye_height (right-hand traffic, left-hand drive). The road is straight or an arc of radius
// curve_radius turning right (> 0) or left (< 0); the sign stands at arc length d along the
// lane's middle, sign_right to the right of it (measured across the road there) and
// sign_height above the road, facing back along the road (normal against the road's
// direction at the sign, tangent horizontal across the road, to the right). Per lamp: the
// observation, entrance, rotation and presentation angles at the sign's centre
// (analysis/photometry.h's conventions, the sign's frame normal n, tangent t, bitangent
// n x t), E_perp = I / r^2 and L_lamp = f(wi, wo) cos(theta_i) E_perp; the sign's luminance
// is the sum over the two lamps.
// The demand: the luminance a driver needs to read the sign, demand_cd_m2, held at every
// distance; the R_A it takes at the driver's geometry, R_A needed = L_demand cos(theta_o) /
// (E_perp,left + E_perp,right), beside the R_A the sheeting supplies there, R_A supplied =
// L cos(theta_o) / (E_perp,left + E_perp,right) (the two lamps' R_A weighted by their
// illuminance). The default demand, 2.4 cd m^-2, is the replacement luminance of Sivak and
// Olson's review of sign legibility research ("Optimal and replacement luminances of traffic
// signs: a review of applied legibility research", UMTRI, 1983) for light backgrounds with
// black legends and light legends on dark backgrounds; Padmos's review for 3M Laboratories
// Europe ("Minimum required night-time luminance of retroreflective traffic signs") puts the
// minimum at 8 to 20 cd m^-2 for a legibility fraction of 0.75, depending on the surround.
// The FHWA minimum-retroreflectivity model (Carlson and Hawkins, FHWA-RD-03-081) combines the
// same terms: the headlamps' illumination of each sign position, the vehicle's size, and a
// demand luminance from legibility studies.
#pragma once

#include <string>
#include <vector>

#include "luminaire.h"
#include "night_render.h"
#include "photometry.h"

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

// A vehicle's lamps and driver's eye (metres). Typical values: the car's eye and lamp heights
// are the design values of Fitzpatrick, Lienau and Fambro (Transp. Res. Rec. 1612, 1998: eye
// 1080 mm, headlamps 600 mm); the rest (lamp spacing, the eye's offset, the SUV and the truck)
// are typical figures, not measurements of a fleet.
struct Vehicle {
    std::string name;
    double lamp_spacing = 0; // between the two lamps' centres
    double lamp_height = 0;  // above the road
    double eye_height = 0;   // above the road
    double eye_left = 0;     // the driver's eye left of the vehicle's middle
};
// car, suv, truck.
const std::vector<Vehicle>& vehicle_presets();
// The preset of that name; InputError naming the presets otherwise.
const Vehicle& vehicle_preset(const std::string& name);

// Where the sign stands (typical values): on the right shoulder, its centre 5.5 m right of the
// lane's middle and 2.1 m above the road; or overhead, above the lane's middle, its centre
// 6.1 m above the road.
enum class SignPosition { Shoulder, Overhead };
SignPosition sign_position(const std::string& name); // "shoulder" or "overhead"
double default_sign_right(SignPosition p);
double default_sign_height(SignPosition p);

struct HeadlampSettings {
    Vehicle vehicle = vehicle_presets()[0];
    double sign_right = 5.5;  // m
    double sign_height = 2.1; // m
    double curve_radius = 0;  // m; 0: straight; > 0 turning right, < 0 left
    double demand_cd_m2 = 2.4;
    double near_m = 30, far_m = 300;
    int steps = 91;
};

// One lamp at the sign's centre.
struct LampAtSign {
    RaGeometry angles;      // degrees
    double intensity = 0;   // cd toward the sign
    double illuminance = 0; // E_perp, lx
    double ra = 0;          // R_A at this lamp's geometry (luminance Y), cd lx^-1 m^-2
    double luminance = 0;   // this lamp's share of the sign's luminance, cd m^-2
};

struct HeadlampPoint {
    double distance = 0;    // m, along the road
    LampAtSign lamps[2];    // left, right
    double luminance = 0;   // cd m^-2, both lamps
    double ra_supplied = 0; // the lamps' R_A weighted by their illuminance
    double ra_needed = 0;   // 0 where the lamps do not light the sign
    double demand = 0;      // cd m^-2
};

// InputError for a curve on which the road turns by more than 90 degrees over far_m (a radius
// other than 0 below far_m / (pi / 2) in magnitude).
std::vector<HeadlampPoint> approach_headlamps(const LobeBrdf& brdf,
                                              const LuminousIntensityDistribution& left,
                                              const LuminousIntensityDistribution& right,
                                              const HeadlampSettings& s);

// Headlamp points as the one-lamp model's points (for the plots): the luminance, R_A supplied,
// the left lamp's angles; with `demand`, the demand and R_A needed instead.
std::vector<ApproachPoint> approach_points(const std::vector<HeadlampPoint>& points,
                                           bool demand = false);

} // namespace retroprism
