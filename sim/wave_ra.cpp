// wave_ra.cpp: R_A of the prisms in physical optics, summed over orientations, averaged over the
// observation azimuth, weighted over wavelengths (see wave_optics.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "error.h"
#include "wave_optics.h"

namespace retroprism {
namespace sim {
namespace wave {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

struct Orientation {
    double psi, weight;
};

std::vector<Orientation> orientations(const WaveMaterial& m, const WaveMode& mode) {
    std::vector<Orientation> list;
    if (mode.era == WaveMode::Era::kAveraged) {
        if (!(mode.orientations >= 1 && mode.orientations <= 100000))
            throw InputError("orientations " + std::to_string(mode.orientations) +
                             ": expected a whole number in [1, 100000]");
        // The uncanted corner (any equal dihedral errors) repeats every 120 degrees; the corner
        // turned by -psi is the mirror image of the one at psi in the plane of incidence (the
        // corner's plane through its cant direction is a mirror plane), and the mean over input
        // polarisations and the observation azimuth (or the coplanar observation) of a mirror
        // image is the same: half the period suffices.
        const std::array<double, 3>& e = m.dihedral_faces_arcmin;
        const bool symmetric = e[0] == e[1] && e[1] == e[2];
        const double half = !symmetric ? 2.0 * kPi : m.cant_deg == 0.0 ? kPi / 3.0 : kPi;
        const int n = symmetric ? mode.orientations : 2 * mode.orientations;
        for (int j = 0; j < n; ++j)
            list.push_back({(j + 0.5) * half / n, 1.0 / n});
        return list;
    }
    if (mode.rotations_deg.empty())
        throw InputError("rotations: expected at least one rotation angle");
    const bool pair = mode.era == WaveMode::Era::kMatchedPair;
    const double w = 1.0 / (double(mode.rotations_deg.size()) * (pair ? 2.0 : 1.0));
    for (double r : mode.rotations_deg) {
        if (!std::isfinite(r)) throw InputError("rotation " + num(r) + ": expected a number");
        list.push_back({r * kDeg, w});
        if (pair) list.push_back({r * kDeg + kPi, w});
    }
    return list;
}

void check_arguments(double entranceDeg, const std::vector<double>& observationDeg, double lambdaNm,
                     const WaveMode& mode) {
    if (!(std::abs(entranceDeg) <= 85.0))
        throw InputError("entrance " + num(entranceDeg) + ": expected a number in [-85, 85]");
    for (double a : observationDeg)
        if (!(a > 0.0 && a <= 20.0))
            throw InputError("observation " + num(a) + ": expected a number in (0, 20]");
    if (!(lambdaNm >= 200.0 && lambdaNm <= 20000.0))
        throw InputError("wavelength " + num(lambdaNm) + ": expected a number in [200, 20000]");
    if (!(mode.azimuth_density >= 0.5 && mode.azimuth_density <= 100.0))
        throw InputError("azimuth_density " + num(mode.azimuth_density) +
                         ": expected a number in [0.5, 100]");
}

// The mean of R_A over the observation azimuth at angle `alpha` (radians) by the trapezoidal
// (midpoint) rule, exact for a periodic function's harmonics below the node count: the nodes
// follow the far field's finest structure, fringes of 2 pi / D across k0 alpha around.
double azimuth_mean(const FarField& ff, double alpha, double diameter, double density) {
    const int n = std::max(16, int(std::ceil(density * ff.k0 * alpha * diameter)));
    double sum = 0;
    for (int j = 0; j < n; ++j)
        sum += ff.ra(observation_direction(ff.pupil.wi, alpha, 2.0 * kPi * (j + 0.5) / n));
    return sum / n;
}

double largest_side(const Polygon& p) {
    double d = 0;
    for (size_t j = 0; j < p.size(); ++j)
        d = std::max(d, glm::length(p[(j + 1) % p.size()] - p[j]));
    return d;
}

} // namespace

WaveMaterial wave_material(const Params& p, double pitchUm) {
    WaveMaterial m;
    m.ior = p.ior;
    m.prism_reflection = p.prism_reflection;
    m.metal_reflectance = p.metal_reflectance;
    m.cant_deg = p.cant_angle;
    m.dihedral_arcmin = p.dihedral_error;
    m.pitch_um = pitchUm;
    return m;
}

WaveMode wave_mode(const Params& p) {
    WaveMode mode;
    mode.era = p.era_mode == f64::RP_ERA_MATCHED_PAIR ? WaveMode::Era::kMatchedPair
               : p.era_mode == f64::RP_ERA_ORIENTED   ? WaveMode::Era::kOriented
                                                      : WaveMode::Era::kAveraged;
    mode.rotations_deg = {p.orientation};
    return mode;
}

namespace {

// The profile of prisms of one pitch (m.pitch_um).
std::vector<double> one_pitch_profile(const WaveMaterial& m, double entranceDeg,
                                      const std::vector<double>& observationDeg, double lambdaNm,
                                      const WaveMode& mode) {
    const double beta = entranceDeg * kDeg;
    const dvec3 wi(std::sin(beta), 0.0, std::cos(beta));
    std::vector<double> ra(observationDeg.size(), 0.0);
    for (const Orientation& o : orientations(m, mode)) {
        const CubeCorner cc = wave_corner(m, o.psi);
        const Pupil pupil = exit_pupil(m, cc, wi, lambdaNm * 1e-3);
        const FarField ff(pupil);
        const double diameter = largest_side(pupil.aperture);
        for (size_t a = 0; a < observationDeg.size(); ++a) {
            const double alpha = observationDeg[a] * kDeg;
            const double v = mode.coplanar
                                 ? ff.ra(dvec3(std::sin(beta - alpha), 0.0, std::cos(beta - alpha)))
                                 : azimuth_mean(ff, alpha, diameter, mode.azimuth_density);
            ra[a] += o.weight * v;
        }
    }
    return ra;
}

} // namespace

std::vector<double> wave_ra_profile(const WaveMaterial& m, double entranceDeg,
                                    const std::vector<double>& observationDeg, double lambdaNm,
                                    const WaveMode& mode) {
    check_material(m);
    check_arguments(entranceDeg, observationDeg, lambdaNm, mode);
    if (!(mode.pitch_spread >= 0.0 && mode.pitch_spread <= 0.5))
        throw InputError("pitch_spread " + num(mode.pitch_spread) +
                         ": expected a number in [0, 0.5]");
    if (mode.pitch_spread == 0.0)
        return one_pitch_profile(m, entranceDeg, observationDeg, lambdaNm, mode);
    if (!(mode.pitch_nodes >= 1 && mode.pitch_nodes <= 1000))
        throw InputError("pitch_nodes " + std::to_string(mode.pitch_nodes) +
                         ": expected a whole number in [1, 1000]");
    std::vector<double> ra(observationDeg.size(), 0.0);
    double areas = 0;
    for (int j = 0; j < mode.pitch_nodes; ++j) {
        WaveMaterial mj = m;
        mj.pitch_um =
            m.pitch_um * (1.0 + mode.pitch_spread * (2.0 * (j + 0.5) / mode.pitch_nodes - 1.0));
        const double area = mj.pitch_um * mj.pitch_um; // the cell's, up to a common factor
        const std::vector<double> r =
            one_pitch_profile(mj, entranceDeg, observationDeg, lambdaNm, mode);
        for (size_t a = 0; a < ra.size(); ++a)
            ra[a] += area * r[a];
        areas += area;
    }
    for (double& v : ra)
        v /= areas;
    return ra;
}

double wave_ra(const WaveMaterial& m, double entranceDeg, double observationDeg, double lambdaNm,
               const WaveMode& mode) {
    return wave_ra_profile(m, entranceDeg, {observationDeg}, lambdaNm, mode)[0];
}

// ---- Photometry -----------------------------------------------------------------------------

std::vector<double> wave_ra_profile_photometric(const WaveMaterial& m, double entranceDeg,
                                                const std::vector<double>& observationDeg,
                                                const WaveMode& mode) {
    std::vector<double> ra(observationDeg.size(), 0.0);
    const std::vector<double>& w = photopic_weights();
    for (size_t j = 0; j < w.size(); ++j) {
        const std::vector<double> r =
            wave_ra_profile(m, entranceDeg, observationDeg, photopic_wavelengths_nm()[j], mode);
        for (size_t a = 0; a < ra.size(); ++a)
            ra[a] += w[j] * r[a];
    }
    return ra;
}

} // namespace wave
} // namespace sim
} // namespace retroprism
