// wave_node.cpp: the node's retro lobe against the wave optics (see wave_node.h).
#include "wave_node.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "error.h"
#include "parallel.h"
#include "parse.h"
#include "wave_optics.h"

namespace retroprism {
namespace sim {
namespace wave {

namespace {

const double kPi = f64::RP_PI; // the core's
const double kDeg = kPi / 180.0;
// The node's roughness floor (the parameter table's note): the smooth top surface of the wave
// optics.
constexpr double kSmoothRoughness = 1e-4;

void require(bool ok, const std::string& what, double v, const std::string& range) {
    if (!ok) throw InputError(what + " " + number_text(v) + ": expected " + range);
}

// The node's R_A at each observation angle: the azimuth mean about wi.
std::vector<double> node_profile(const Params& material, const NodeWaveCase& c,
                                 const std::vector<double>& observationDeg) {
    const PrismaticRetroreflector<double> node(node_wave_params(material, c));
    const double beta = c.entrance_deg * kDeg;
    const glm::dvec3 wi(std::sin(beta), 0.0, std::cos(beta));
    std::vector<double> ra;
    for (double a : observationDeg) {
        double sum = 0;
        for (int j = 0; j < kNodeWaveAzimuths; ++j) {
            const glm::dvec3 wo =
                observation_direction(wi, a * kDeg, 2 * kPi * (j + 0.5) / kNodeWaveAzimuths);
            sum += node.f(wi, wo).retro.x * wi.z * wo.z / kNodeWaveAzimuths;
        }
        ra.push_back(sum);
    }
    return ra;
}

// The wave optics' material of case c.
WaveMaterial case_material(const Params& material, const NodeWaveCase& c) {
    WaveMaterial m = wave_material(material, c.pitch_um);
    m.prism_reflection = c.prism;
    return m;
}

} // namespace

Params node_wave_params(const Params& material, const NodeWaveCase& c) {
    Params p = material;
    p.roughness = kSmoothRoughness;
    p.specular = 0.0;
    p.diffuse_color = {0.0, 0.0, 0.0};
    p.retro_color = {1.0, 1.0, 1.0};
    p.weight = 1.0;
    p.abbe_number = 0.0;
    p.dihedral_spread = 0.0;
    p.prism_reflection = c.prism;
    p.prism_pitch = c.pitch_um;
    p.wavelength = c.nm;
    return p;
}

void check_case(const NodeWaveCase& c) {
    require(c.prism >= 0 && c.prism <= 2, "prism_reflection", c.prism,
            "0 (ideal), 1 (tir) or 2 (metallized)");
    require(c.pitch_um >= 1.0 && c.pitch_um <= 2000.0, "pitch", c.pitch_um,
            "a number in [1, 2000] um");
    require(c.nm >= 200.0 && c.nm <= 2000.0, "wavelength", c.nm, "a number in [200, 2000] nm");
    require(std::abs(c.entrance_deg) <= 85.0, "entrance", c.entrance_deg,
            "a number in [-85, 85] deg");
}

std::vector<NodeWaveProfile> node_wave_profiles(const Params& material,
                                                const std::vector<NodeWaveCase>& cases,
                                                const std::vector<double>& observationDeg,
                                                double pitchSpread, int threads) {
    for (const NodeWaveCase& c : cases) {
        check_case(c);
        check_material(case_material(material, c));
    }
    for (double a : observationDeg)
        require(a > 0.0 && a <= 20.0, "observation", a, "a number in (0, 20] deg");
    require(pitchSpread >= 0.0 && pitchSpread <= 0.5, "pitch_spread", pitchSpread,
            "a number in [0, 0.5]");
    WaveMode mode = wave_mode(material);
    mode.pitch_spread = pitchSpread;
    std::vector<NodeWaveProfile> out(cases.size());
    parallel_for(cases.size(), threads, [&](size_t i) {
        const NodeWaveCase& c = cases[i];
        out[i].c = c;
        out[i].wave =
            wave_ra_profile(case_material(material, c), c.entrance_deg, observationDeg, c.nm, mode);
        out[i].node = node_profile(material, c, observationDeg);
    });
    return out;
}

std::vector<double> node_wave_ratios(const NodeWaveProfile& p) {
    std::vector<double> r;
    for (size_t a = 0; a < p.node.size() && a < p.wave.size(); ++a)
        r.push_back(p.node[a] / p.wave[a]);
    return r;
}

NodeWaveCounts node_wave_counts(const std::vector<double>& ratios) {
    NodeWaveCounts n;
    double worst = 0; // the largest |log ratio|
    for (double r : ratios) {
        ++n.entries;
        n.within10 += std::abs(r - 1) <= 0.10;
        n.within2x += r >= 0.5 && r <= 2.0;
        worst = std::isfinite(r) && r > 0 ? std::max(worst, std::abs(std::log(r))) : INFINITY;
    }
    n.worst_factor = std::exp(worst);
    return n;
}

NodeWaveTable node_wave_table(int fidelity, double pitchSpread, int threads) {
    std::vector<NodeWaveCase> cases;
    for (int prism : {0, 1})
        for (double pitch : {100.0, 250.0})
            for (double nm : {550.0, 905.0, 1550.0})
                for (double entrance : {-4.0, 15.0, 30.0, 45.0})
                    cases.push_back({prism, pitch, nm, entrance});
    Params material;
    material.ior = 1.49;
    material.fidelity = fidelity;
    NodeWaveTable t;
    t.profiles =
        node_wave_profiles(material, cases, kNodeWaveTableObservations, pitchSpread, threads);
    std::vector<double> ratios;
    for (const NodeWaveProfile& p : t.profiles)
        for (double r : node_wave_ratios(p))
            ratios.push_back(r);
    t.counts = node_wave_counts(ratios);
    return t;
}

} // namespace wave
} // namespace sim
} // namespace retroprism
