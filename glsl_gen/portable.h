// portable.h: the node's portable implementation, a MaterialX <nodegraph> of standard 1.39 nodes
// (stdlib and pbrlib) that MaterialX chooses for every target without an implementation of ours
// (OSL, MDL); GLSL, ESSL, Vulkan GLSL and MSL keep the exact genglsl implementation.
//
// The graph sees the view direction V and the normal N only (a BSDF node alone knows the light
// direction), so every factor of the model is evaluated at the view direction, where it is
// exact at the retro peak (wi = wo):
//   surface  dielectric_bsdf, Fresnel of ior, GGX of the Beckmann roughness alpha (equal alpha:
//            the two NDFs have the same peak, 1 / (pi alpha^2));
//   retro    generalized_schlick_bsdf with constant Fresnel c_r E(mu_t) T(cos_v)^2 and its normal
//            set to V: a GGX lobe about the view direction, of width kPortableRetroFit.width
//            alpha_o / 2 (a reflected direction spreads twice as wide as the half vector), with
//            alpha_o the model's isotropic width at V (retro_lobe anisotropic: alpha_par along
//            the lobe's tangent in the plane of incidence, alpha_perp across) and the Beckmann
//            shape fitted by one GGX lobe (fit_retro_lobe); with a prism pitch two such lobes
//            sharing the diffraction pattern (fit_diffraction_lobes);
//   diffuse  oren_nayar_diffuse_bsdf (roughness 0: Lambert) of colour
//            k_d T(cos_v)^2 (1 - E) / (eta^2 (1 - k_d F_dr(eta))).
// With era_mode averaged, E is the azimuth-averaged ERA of ideal prisms as a polynomial in
// (sin theta_t, cant_angle) (times fits for uncoated and metallised prisms, below), and F_dr(eta)
// a polynomial in eta, least-squares fits of the C++ model made when the graph is generated
// (fit_era, fit_fdr); with matched pairs and single orientations, E is the node's closed form for
// the prisms at their azimuth (the direction refracted from V in the frame of the normal and
// tangent, the cube's faces at cant_angle turned by orientation). T is the exact Fresnel
// transmittance, as nodes.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace retroprism::glsl {

// An input of the node the portable graph does not honour, and why.
struct PortableException {
    std::string input;
    std::string reason;
};
// The inputs the graph cannot honour (every other input of the parameter table reaches it).
const std::vector<PortableException>& portable_exceptions();

// A least-squares polynomial fit: value = sum_ij coef[i][j] u^i v^j with u and v the fit's
// variables mapped onto [-1, 1] (v absent for a fit of one variable: coef[i] has one entry).
struct PolyFit {
    std::vector<std::vector<double>> coef;
    double max_error = 0; // largest |fit - model| over the fit's grid
    double rms_error = 0;
    double max_rel_error = 0; // fit_tir_ratio: largest |fit / model - 1| where it is weighted
};

// The azimuth-averaged ERA A of ideal prisms over u = 2 sin(theta_t) - 1 and v = cant / 30 deg.
const PolyFit& fit_era();
// F_dr(eta), the internal hemispherical-diffuse reflectance, over u = eta - 2 (eta in [1, 3]).
const PolyFit& fit_fdr();

// Uncoated (tir) prisms: E = A Q with A the ideal prisms' ERA and Q the mean product of the
// three faces' reflectances over the retroreflecting aperture. Q is 1 until the refracted
// direction tilts one face's incidence below the critical angle: for the paper's cube, at
// theta_t = kCubeFaceAngle - asin(1 / eta) (the face normals are kCubeFaceAngle from the cube
// axis). Q is fitted as a function of z = tir_onset(sin theta_t, eta), the tilt beyond that
// onset as a fraction of its largest value at eta (2 asin(1 / eta) - kCubeFaceAngle, at grazing
// incidence; 0 before the onset), over u = 2 z - 1 and v = eta - 2, eta in the node's [1, 3]:
// a rectangle in (u, v), so that the coefficients stay small enough for single precision.
// Least squares of Q, weighted toward the sheeting plastics; the errors are those of E = A Q
// against PrismaticRetroreflector<double>::retro_fraction with prism_reflection tir (era
// averaged), cant 0.
constexpr double kCubeFaceAngle = 0.9553166181245093; // acos(1 / sqrt 3)
// The span below which the onset's range counts as empty (eta above 2.17: total internal
// reflection at every incidence in the plane of the fit).
constexpr double kTirMinSpan = 1e-3;
double tir_onset(double sinT, double eta);
const PolyFit& fit_tir_ratio();
// Metallized prisms: sum_k H_k, the mean number of faces a ray entering the aperture meets
// (prism_core.inc), azimuth-averaged for the uncanted cube, over u = 2 sin(theta_t) - 1.
const PolyFit& fit_metal_hits();

// One GGX lobe D about V of roughness `width` alpha_o / 2, times `scale`, fitted to the Beckmann
// direction lobe p_o(theta') = exp(-x) / (pi alpha_o^2 cos^3), x = tan^2 theta' / alpha_o^2,
// with the smallest largest relative error over x in [0, kRetroFitRange] (the lobe above 1/e of
// its peak): `scale` / width^2 is its value at the peak relative to p_o's, `scale` its
// integral relative to p_o's.
struct RetroLobeFit {
    double width = 1;
    double scale = 1;
    double max_error = 0;
};
constexpr double kRetroFitRange = 1.0;
const RetroLobeFit& fit_retro_lobe();

// Diffraction (prism_pitch > 0): the node's pattern of the prisms (rp_diffraction_channel) at
// normal incidence, azimuth-averaged, as a density of nu = theta' pitch / lambda, fitted by
// kDiffractionLobes GGX lobes about V: lobe k of the geometric lobe's tint times `weight[k]`
// (fit_retro_lobe's scale included) whose widths add sigma[k]^2 (lambda / pitch)^2 to the
// geometric lobe's squared widths as the node's Gaussian terms add their variances (divided by
// cos_v^2 along the plane of incidence), the smallest largest relative error over nu in
// [kDiffractionFitLo, kDiffractionFitHi] (the R_A tables' 0.2-2 degrees for pitches of 50-300
// um in the visible and the near infrared). One fit per kind of prism face (prism_reflection
// 0-2); off normal incidence the graph widens the lobes by the aperture's shrinking,
// A(0) / A with A the ideal prisms' ERA (fit_era): the pattern's solid angle is lambda^2 over
// the aperture's area.
constexpr int kDiffractionLobes = 2;
constexpr double kDiffractionFitLo = 0.1;
constexpr double kDiffractionFitHi = 12.0;
struct DiffractionLobesFit {
    double weight[kDiffractionLobes] = {1, 0};
    double sigma[kDiffractionLobes] = {0, 0};
    double max_error = 0; // largest |ln(fit / node)| over the fit's range
};
const DiffractionLobesFit& fit_diffraction_lobes(int prismReflection);

// The nodegraph document (rp_pbrlib_ng.mtlx) implementing ND_rp_prismatic_retroreflector_bsdf.
// Throws std::runtime_error when an input of the parameter table neither reaches the graph nor
// is a listed exception.
std::string generate_portable_nodegraph();

} // namespace retroprism::glsl
