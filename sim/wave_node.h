// wave_node.h: the node's retro lobe (PrismaticRetroreflector<double>) against the physical-optics
// ground truth (wave_optics.h): R_A of the prisms alone, averaged over the observation azimuth,
// the node's beside the wave optics' (docs/diffraction.md#against-physical-optics; `retroprism
// simulate --wave --against-node`).
//
// Conventions: R_A in sr^-1 (cd lx^-1 m^-2), as wave_optics.h; the node's is the azimuth mean of
// f_retro(wi, wo) cos(theta_i) cos(theta_o) (its first channel; every channel is evaluated at the
// case's wavelength) over kNodeWaveAzimuths directions at the observation angle about wi
// (wave::observation_direction), wi = (sin, 0, cos) of the signed entrance angle. The node is
// made the prisms alone, as the wave optics model them: a smooth top surface (roughness 1e-4:
// its geometric lobe is 0.004 deg wide), no surface lobe (specular 0), no substrate
// (diffuse_color 0), retro_color 1 and weight 1, no dispersion (abbe_number 0: both at the
// material's ior), no random dihedral errors (dihedral_spread 0); the rest of the material
// (ior, metal_reflectance, era_mode, orientation, cant and dihedral errors, retro_lobe, fidelity)
// is both sides'. The wave optics sum the material's orientations (wave_mode) over prisms of
// pitches spread +- pitchSpread (WaveMode::pitch_spread), which fills the rings of one size.
#pragma once

#include <vector>

#include "prismatic_retroreflector.h"

namespace retroprism {
namespace sim {
namespace wave {

// Observation azimuths of the node's mean (the midpoint rule over the turn).
constexpr int kNodeWaveAzimuths = 64;

// One case of the comparison: the faces, the groove spacing, the wavelength, the entrance angle.
struct NodeWaveCase {
    int prism = 1;              // prism_reflection: 0 ideal, 1 uncoated (tir), 2 metallized
    double pitch_um = 150.0;    // groove spacing, [1, 2000] um
    double nm = 550.0;          // wavelength, [200, 2000] nm
    double entrance_deg = -4.0; // signed entrance angle, [-85, 85] deg
};

// R_A (sr^-1) per observation angle of one case.
struct NodeWaveProfile {
    NodeWaveCase c;
    std::vector<double> node, wave;
};

// The node's parameters of case `c` for `material` (the conventions above).
Params node_wave_params(const Params& material, const NodeWaveCase& c);

// Throws InputError naming the field and its range unless: prism in {0, 1, 2}, pitch_um in
// [1, 2000] (the node's prism_pitch above 0 and the wave optics' pitch), nm in [200, 2000] (the
// node's wavelength and the wave optics'), entrance_deg in [-85, 85].
void check_case(const NodeWaveCase& c);

// The node's and the wave optics' R_A of each case at each observation angle (degrees, in
// (0, 20]), the cases spread over up to `threads` threads (0: one per core; the values do not
// depend on it). Throws InputError naming the parameter and its range for a bad case, a bad
// observation angle, pitchSpread outside [0, 0.5] or a material the wave optics reject
// (check_material) before computing anything.
std::vector<NodeWaveProfile> node_wave_profiles(const Params& material,
                                                const std::vector<NodeWaveCase>& cases,
                                                const std::vector<double>& observationDeg,
                                                double pitchSpread, int threads = 0);

// How many ratios node / wave of `ratios` are within 10% and within a factor 2, and the largest
// factor max(ratio, 1 / ratio) (1 when none; a zero or non-finite ratio counts as neither and
// sets the factor to infinity).
struct NodeWaveCounts {
    long entries = 0, within10 = 0, within2x = 0;
    double worst_factor = 1.0;
};
NodeWaveCounts node_wave_counts(const std::vector<double>& ratios);
// The ratios node / wave of a profile.
std::vector<double> node_wave_ratios(const NodeWaveProfile& p);

// The standard tables (the [wave][ci] test, docs/diffraction.md): ideal and uncoated faces, ior
// 1.49 and the node's fidelity tier `fidelity` (0 exact, 1 fast; otherwise the node's defaults),
// pitches 100 and 250 um, 550, 905 and 1550 nm, entrance -4, 15, 30 and 45 deg, observation
// 0.1-2 deg (kNodeWaveTableObservations), the wave optics' pitches spread +-pitchSpread: its
// profiles, in that nesting order, and their counts over all entries. The exact tier's table is
// taken at one pitch (spread 0: the pattern the exact tier evaluates), the fast tier's at
// kNodeWaveTablePitchSpread (prisms of several sizes, whose rings its smooth form fills).
inline const std::vector<double> kNodeWaveTableObservations = {0.1, 0.2, 0.33, 0.5,
                                                               0.7, 1.0, 1.5,  2.0};
constexpr double kNodeWaveTablePitchSpread = 0.15;
struct NodeWaveTable {
    std::vector<NodeWaveProfile> profiles;
    NodeWaveCounts counts;
};
NodeWaveTable node_wave_table(int fidelity, double pitchSpread, int threads = 0);

} // namespace wave
} // namespace sim
} // namespace retroprism
