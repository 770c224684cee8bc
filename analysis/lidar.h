// lidar.h: the return of a LiDAR from a flat target of a material: `retroprism lidar`.
//
// The LiDAR equation with the BRDF integrated over the receiver's aperture and the beam's
// footprint, for a near-monostatic sensor (emitter and receiver a few centimetres apart), where a
// retroreflector's return is read at observation angles of hundredths to tenths of a degree, on
// the retro lobe's shape. Assumptions: geometric optics between the sensor and the target (the
// BRDF is the target's far field, valid from a few pitch^2 / lambda, centimetres, away); an
// incoherent return (no speckle); no atmosphere; the receiver sees the whole footprint (its field
// of view holds the beam) and the emitter does not shade it; no multiple bounces.
//
// Geometry (metres, the sensor frame):
//  - The emitter at the origin, the beam's axis +z, y up. The beam is a Gaussian of full
//    divergence `divergence_mrad` at its 1/e^2 irradiance, from a point: the power per unit of
//    a ray's slopes s = (x/z, y/z) is P g(s), g(s) = 2 / (pi t^2) exp(-2 |s|^2 / t^2),
//    t = tan(divergence / 2). g integrates to 1, so a plane across the beam receives all of it
//    (no waist: the far field of the emitter's optics). Rays beyond |s| = kBeamTruncation t
//    carry exp(-2 kBeamTruncation^2) of the power and are left out.
//  - The receiver: a disc of diameter `aperture_m`, centre `receiver_offset`, facing +z.
//  - The target: a rectangle whose centre is on the beam's axis at `range_m`, turned by the
//    entrance angle beta about y: normal (sin beta, 0, -cos beta) toward the sensor, width along
//    (-cos beta, 0, -sin beta), height along +y; width and height 0: larger than the footprint.
//    The material's frame: normal the target's, tangent (the prisms' datum mark, the node's
//    local +x) the width's direction turned by the rotation angle epsilon about the normal,
//    counter-clockwise seen from the front: photometry.h's beta and epsilon, so that at the
//    target's centre wi = (sin beta, 0, cos beta) in the material's frame before the rotation.
//
// Radiometry: a ray of power dP meets the target at x; the receiver collects dP rho_ap(x), with
// rho_ap(x) = integral over the aperture of f(wi, wo) cos(theta_o) dOmega(y), wi toward the
// emitter, wo toward the aperture's point y, dOmega = cos(y) dA_y / |y - x|^2 (cos(y) at the
// aperture): `aperture_reflectance`, the per-ray function of a ray-traced LiDAR. The returned
// fraction P_r / P is the integral of g(s) rho_ap(x(s)) over the rays that meet the target.
// For a Lambertian target (f = rho / pi) rho_ap is rho times the view factor of the aperture
// from x; far from the sensor, P_r / P = rho cos(beta) D^2 / (4 R^2) for a target larger than
// the footprint (the textbook LiDAR equation), and falls as R^-4 once the footprint outgrows it.
//
// Intensity convention: the equivalent Lambertian reflectance, P_r over the return of a
// Lambertian target of reflectance 1 of the same size in the same geometry. A LiDAR calibrated
// on Lambertian targets reports it as reflectivity: a grey Lambertian target of reflectance rho
// reads rho at any range and angle; a retroreflector reads far above 1.
//
// Quadrature: the footprint by Gauss-Legendre in the target's plane over the rectangle clipped
// to the beam's truncation, in two panels per axis split at the beam's centre; the aperture in
// polar coordinates about the point where the retro direction (back toward the emitter) meets
// the aperture's plane when that point is inside the disc (else about the disc's centre), the
// radius in geometric panels toward that point, so a narrow retro lobe is resolved.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "prismatic_retroreflector.h"

namespace retroprism {

// Rays beyond this many 1/e^2 beam radii (in slope) carry exp(-32) = 1.3e-14 of the power.
constexpr double kBeamTruncation = 4.0;

// A BRDF f(wi, wo) in 1/sr without the cosine, directions in the material's local frame
// (normal +z, tangent +x), one channel. Zero below the horizon.
using LidarBrdf = std::function<double(const glm::dvec3& wi, const glm::dvec3& wo)>;

// The node of `material` (in the local frame: ra_params) at `wavelengthNm`, through the node's
// evaluation at a wavelength (the diffraction of prism_pitch at it, the index there with
// abbe_number), channel `channel` (0 red, 1 green, 2 blue: the colour inputs' channel; the
// node's colours are not spectral, so at infrared wavelengths the red channel, the nearest, is
// the one to use). InputError for a wavelength outside (0, 2000] nm or a channel outside 0-2.
LidarBrdf lidar_node_brdf(const Params& material, double wavelengthNm, int channel = 0);

// The node's directional albedo (integral of f cos(theta_o)) at `wavelengthNm`, channel
// `channel`, for light at entrance angle `entranceDeg` and rotation `rotationDeg` (photometry.h's
// beta and epsilon): the reflectance of a Lambertian target "of the same albedo".
double lidar_node_albedo(const Params& material, double wavelengthNm, int channel,
                         double entranceDeg, double rotationDeg = 0.0);

// A BRDF of a Lambertian reflector of reflectance rho: rho / pi above the horizon.
LidarBrdf lambertian_brdf(double rho);

struct LidarSensor {
    glm::dvec3 receiver_offset{0.03, 0.0, 0.0}; // m, the aperture's centre from the emitter
    double divergence_mrad = 3.0;               // full angle at the 1/e^2 irradiance
    double aperture_m = 0.025;                  // the receiver aperture's diameter
};

struct LidarTarget {
    double range_m = 20.0;   // emitter to the target's centre along the beam's axis
    double entrance_deg = 0; // beta, in (-90, 90)
    double rotation_deg = 0; // epsilon: the material's datum mark about the target's normal
    double width_m = 0;      // 0 (with height 0): larger than the footprint
    double height_m = 0;
};

// Quadrature orders (the defaults' error is measured by the [lidar] test against doubled
// orders and against an independent integration).
struct LidarQuadrature {
    int footprint = 12;      // Gauss-Legendre nodes per panel, two panels per axis
    int aperture_radial = 6; // Gauss-Legendre nodes per radial panel, kApertureRadialPanels
    int aperture_angular = 32;
};
// Radial panels of the aperture's polar rule: edges at 4^-k of the radius, k = panels-1..0.
constexpr int kApertureRadialPanels = 4;

// InputError naming the input (the command's option name) and its allowed range for any input
// outside it: receiver_offset finite with length at most range / 10, divergence in (0, 100] mrad,
// aperture in (0, 1] m and at most range / 10, range in [0.1, 1e5] m, entrance in (-90, 90)
// degrees with the whole truncated beam meeting the target's plane in front of the sensor,
// rotation finite, width and height both 0 or both in (0, 1e4] m; quadrature orders in [1, 64],
// the angular one in [4, 256].
void check_lidar_inputs(const LidarSensor& sensor, const LidarTarget& target,
                        const LidarQuadrature& q = {});

// A point of a surface hit by a LiDAR ray, in any one frame: position, the surface's normal
// (toward the side the ray comes from) and its tangent (the material's local +x).
struct LidarHit {
    glm::dvec3 position{0.0};
    glm::dvec3 normal{0.0, 0.0, 1.0};
    glm::dvec3 tangent{1.0, 0.0, 0.0};
};
// A receiver aperture: a disc of diameter `diameter` at `centre`, facing along `axis`.
struct LidarAperture {
    glm::dvec3 centre{0.0};
    glm::dvec3 axis{0.0, 0.0, 1.0};
    double diameter = 0.025;
};

// rho_ap: the fraction of a ray's power, arriving at `hit` from `emitter`, that the aperture
// collects (integral of f cos(theta_o) dOmega over the aperture); 0 when the emitter or the
// aperture's centre is behind the surface. Aperture points behind the surface or seeing the
// aperture from behind count 0. The per-ray function of a ray-traced LiDAR.
double aperture_reflectance(const LidarBrdf& f, const LidarHit& hit, const glm::dvec3& emitter,
                            const LidarAperture& aperture, const LidarQuadrature& q = {});

struct LidarReturn {
    double fraction = 0;            // P_r / P
    double lambertian_fraction = 0; // P_r / P of a Lambertian target of reflectance 1
    double reflectance = 0;         // equivalent Lambertian reflectance: fraction / lambertian
    double intercepted = 0;         // the fraction of the beam's power on the target
    double observation_mrad = 0;    // at the target's centre: between emitter and aperture centre
};

// The return of a target of BRDF f (InputError from check_lidar_inputs first).
LidarReturn lidar_return(const LidarBrdf& f, const LidarSensor& sensor, const LidarTarget& target,
                         const LidarQuadrature& q = {});

// A material of a sweep.
struct LidarMaterial {
    std::string label;
    Params params;
};

// `retroprism lidar`'s material argument "[LABEL=]FILE.json|DOC.mtlx": a material file's inputs
// or a MaterialX document's first material, labelled LABEL or the file's path; InputError `<arg>:
// expected a material FILE.json or a MaterialX document DOC.mtlx` for another file name.
LidarMaterial lidar_material(const std::string& arg);

// One row of a sweep: a material at a wavelength, range and entrance angle (the other inputs
// the sweep's sensor and target), with the Lambertian target of the same albedo beside it.
struct LidarRow {
    std::string material;
    double wavelength_nm = 0;
    double range_m = 0;
    double entrance_deg = 0;
    double observation_mrad = 0;
    LidarReturn ret;
    double albedo = 0;            // the node's directional albedo at the entrance angle
    double lambertian_albedo = 0; // P_r / P of the Lambertian target of that albedo
};

// Every material x wavelength x entrance x range, in that nesting order (ranges innermost).
std::vector<LidarRow> lidar_sweep(const std::vector<LidarMaterial>& materials,
                                  const LidarSensor& sensor, const LidarTarget& target,
                                  const std::vector<double>& wavelengthsNm,
                                  const std::vector<double>& rangesM,
                                  const std::vector<double>& entrancesDeg, int channel = 0,
                                  const LidarQuadrature& q = {});

// The returns of another BRDF `f` at the geometries of a sweep's rows (their range and entrance
// angle, the sweep's sensor and target otherwise; f is at one wavelength and channel already):
// a model beside the rows' materials, such as the MaterialX-style GGX fitted to a sheeting's R_A
// table (lidar_ggx_brdf).
std::vector<LidarReturn> lidar_returns_at(const LidarBrdf& f, const std::vector<LidarRow>& rows,
                                          const LidarSensor& sensor, const LidarTarget& target,
                                          const LidarQuadrature& q = {});

// The MaterialX-style retroreflective GGX over a Lambertian base (nodes/baselines.h) fitted to
// the R_A table `tableCsv` as `retroprism fit --ra` fits it (analysis/ra_fit.h), channel
// `channel`: the renderers' common retroreflection model set from a sheeting's datasheet. Not
// spectral: the same at every wavelength.
LidarBrdf lidar_ggx_brdf(const std::string& tableCsv, int channel = 0);

} // namespace retroprism
