// fitting.h: fitting the node, and the MaterialX-style retroreflective GGX baseline, to
// measured BRDF x cos(theta_o) samples (`retroprism fit`).
//
// The measured quantity is y = f(wi, wo) cos(theta_o) [1/sr], one channel (colours are fitted
// grey). What is fitted, and how:
//  - Node: roughness alpha, ior eta, specular k_s, retro_color c_r, diffuse_color k_d,
//    prism_reflection (ideal | tir | metallized, a discrete choice: each is fitted and the best
//    kept) and the sheeting geometry: cant_angle, dihedral_error and dihedral_spread in their
//    ranges of the
//    parameter table (RP_FIT), or held at 0 (the paper's cube) with paper_geometry. Other inputs
//    keep their defaults (era_mode averaged: the data are isotropic; metal_reflectance 0.88;
//    retro_lobe isotropic; reciprocal false).
//  - Baseline ("mrm"): baselines::RetroreflectiveGGX: GGX roughness, ior, specular weight and a
//    grey Lambert colour (the exact model is written in nodes/baselines.h).
//  - Objective: weighted log residuals r = ln(m + eps) - ln(y + eps), eps = floor_fraction x the
//    median measured value (so near-zero samples at grazing angles do not dominate). Weights:
//    every incidence angle theta_l carries the same total weight; within it, the "peak" samples
//    (y > peak_factor x that angle's median) and the "floor" samples carry half each. Thus the
//    few samples on the retro and mirror peaks count as much as the thousands on the floor.
//  - Instrument resolution: the measured value is modelled as the BRDF convolved with a
//    Gaussian blur of the outgoing direction of FWHM `resolution_fwhm_deg` (sigma = FWHM /
//    2.3548). For the peaked lobes this is done analytically: a Beckmann (or GGX) lobe convolved
//    with a narrow Gaussian is, to first order in angle, the same lobe with the variances added.
//    Node surface lobe: alpha_s^2 = alpha^2 + sigma^2 / 2 (the mirror direction moves twice as
//    fast as the microfacet normal); retro lobe: the roughness alpha_r whose lobe width is
//    alpha_o(alpha_r)^2 = alpha_o(alpha)^2 + 2 sigma^2 (alpha_o = k alpha, MODEL.md section 3,
//    k = sqrt(2) |eta cos theta_t - cos theta_i| / sqrt(cos theta_i)); GGX (near its peak a
//    Gaussian of slope variance alpha^2 / 4): alpha_eff^2 = alpha^2 + sigma^2. The diffuse lobes
//    are smooth at this scale and evaluated as they are. Exact in the plane of incidence for the
//    retro lobe; out of that plane the mirror lobes are narrower by cos(theta_i), so there the
//    widening is slightly too small. The reported parameters are the material's (alpha), not the
//    widened ones.
//  - Optimiser (deterministic): the colours and weights enter linearly (the node: k_s, c_r and
//    c_d = k_d (1 - F_dr) / (1 - k_d F_dr); the baseline: k_s and k_d up to the layer's k_s k_d
//    cross term), so for each (alpha, eta) they are solved in [0, 1] by a projected
//    Levenberg-Marquardt (variable projection); the shape inputs are searched by search_box
//    (util/minimize.h: Nelder-Mead in logistic coordinates, restarted from the best until it
//    stops improving): first (alpha, eta) with the paper's geometry (alpha in [0.001, 1], eta in
//    [1.01, 3], linear) from 3 starts (alpha 0.01, 0.05, 0.2; eta 1.5), then (alpha, eta,
//    cant_angle, dihedral_error, dihedral_spread) from that optimum with 5 geometries (the
//    paper's; dihedral_error at the centre of its range; that with the cant at 12% and 88% of
//    its range; dihedral_spread alone at the centre of its range). The paper's
//    geometry is kept when the second search does not improve on it, so fitting the geometry
//    never worsens the fit. With fixed_ior the ior is not searched.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "alta_reader.h"
#include "baselines.h"
#include "prismatic_retroreflector.h"

namespace retroprism {

struct FitSample {
    glm::dvec3 wi{0, 0, 1}, wo{0, 0, 1};
    double value = 0; // BRDF x cos(theta_o), 1/sr
    int group = 0;    // index into FitData::group_theta
    int line = 0;     // line in the data file (0: synthetic)
};

struct FitData {
    std::string file;
    std::vector<FitSample> samples;
    std::vector<double> group_theta; // incidence angle of each group, radians (wi at phi = 0)
};

// The samples of an ALTA file, grouped by theta_l (equal to 1e-9 rad).
FitData fit_data(const AltaData& alta);
// Appends a sample, creating its group when theta_l is new.
void add_sample(FitData& d, double thetaL, const glm::dvec3& wo, double value, int line = 0);

struct FitOptions {
    double resolution_fwhm_deg = 1.07;
    double floor_fraction = 0.05;
    double peak_factor = 4.0;
    double fixed_ior = 0;        // > 0: the ior of both models is fixed to this instead of fitted
    int threads = 0;             // 0: one per core; the results do not depend on it
    bool paper_geometry = false; // true: cant_angle and the dihedral errors held at 0, not fitted
};

// The node's fitted inputs (grey colours).
struct NodeFitParams {
    double roughness = 0.05;
    double ior = 1.49;
    double specular = 1.0;
    double retro = 1.0;   // retro_color
    double diffuse = 0.9; // diffuse_color
    int prism_reflection = 0;
    double cant_angle = 0;      // degrees
    double dihedral_error = 0;  // arcminutes
    double dihedral_spread = 0; // arcminutes
};
Params node_params(const NodeFitParams& p);

// Model values (BRDF x cos(theta_o), blurred as described above) at every sample.
std::vector<double> node_values(const NodeFitParams& p, const FitData& d, const FitOptions& o);
std::vector<double> mrm_values(const baselines::RetroreflectiveGGX& m, const FitData& d,
                               const FitOptions& o);

struct GroupReport {
    double theta_deg = 0;
    int samples = 0;
    double rel_rms = 0, log_rms = 0;
    // The highest measured sample within 3 degrees of the retro (wo = wi) and mirror
    // directions, and the model there (0 when the group has no sample there).
    double retro_measured = 0, retro_model = 0;
    double mirror_measured = 0, mirror_model = 0;
};

struct FitReport {
    double objective = 0; // the weighted objective (sum of w r^2, weights summing to 1)
    double rel_rms = 0;   // sqrt(mean(((m - y) / y)^2)), every sample equally
    double log_rms = 0;   // sqrt(mean(ln((m + eps) / (y + eps))^2)), every sample equally
    double epsilon = 0;
    std::vector<GroupReport> groups;
};

FitReport fit_report(const FitData& d, const std::vector<double>& model, const FitOptions& o);

struct NodeFit {
    NodeFitParams params;
    FitReport report;
    double mode_objective[3] = {0, 0, 0};  // best objective per prism_reflection
    double paper_objective[3] = {0, 0, 0}; // the same with the paper's geometry (cant and
                                           // dihedral error 0)
    int evaluations = 0;                   // shape evaluations (alpha, eta, geometry)
};

struct MrmFit {
    baselines::RetroreflectiveGGX model;
    FitReport report;
    int evaluations = 0;
};

NodeFit fit_node(const FitData& d, const FitOptions& o);
MrmFit fit_mrm(const FitData& d, const FitOptions& o);

} // namespace retroprism
