#include "trade.h"

#include <array>
#include <chrono>
#include <cmath>

#include "backend.h"
#include "check.h"
#include "embedded_files.h"
#include "gl_runner.h"
#include "glsl_gen.h"
#include "study_results.h"

namespace retroprism::bench {

void reference_errors(const Row& row, Result& res) {
    const std::vector<DirectionPair> pairs = standard_pairs(row.material);
    const LocalEval f = row.make_eval(row.material);
    const PrismaticRetroreflector<double> ref(row.reference);
    std::vector<std::array<glm::dvec3, 3>> got(pairs.size()), want(pairs.size());
    double peak[3] = {0, 0, 0};
    for (size_t i = 0; i < pairs.size(); ++i) {
        const glm::dvec3 wi(pairs[i].wi[0], pairs[i].wi[1], pairs[i].wi[2]);
        const glm::dvec3 wo(pairs[i].wo[0], pairs[i].wo[1], pairs[i].wo[2]);
        f(wi, wo, got[i].data());
        const auto e = ref.eval(wi, wo);
        want[i] = {e.f.surface, e.f.retro, e.f.diffuse};
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c)
                peak[k] = std::max(peak[k], std::abs(want[i][size_t(k)][c]));
    }
    double l1 = 0, l1ref = 0, l2 = 0, l2ref = 0, worst = 0, retroPeak = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            if (!(row.mask & (1 << k))) continue;
            for (int c = 0; c < 3; ++c) {
                const double a = got[i][size_t(k)][c], b = want[i][size_t(k)][c];
                l1 += std::abs(a - b);
                l1ref += std::abs(b);
                l2 += (a - b) * (a - b);
                l2ref += b * b;
                if (std::abs(b) >= 1e-3 * peak[k] && b != 0)
                    worst = std::max(worst, std::abs(a - b) / std::abs(b));
            }
        }
        if ((row.mask & 2) && pairs[i].wi == pairs[i].wo && want[i][1].x > 0)
            retroPeak = std::max(retroPeak, std::abs(got[i][1].x / want[i][1].x - 1.0));
    }
    res.error = l1ref > 0 ? l1 / l1ref : 0;
    res.rms = l2ref > 0 ? std::sqrt(l2 / l2ref) : 0;
    res.worst = worst;
    if (row.mask & 2) res.retroPeak = retroPeak;
}

std::vector<SimConfig> read_study(const std::string& path) {
    std::vector<SimConfig> out;
    for (const sim::ConfigResult& r : sim::read_results_csv(path))
        out.push_back({r.c.theta, r.c.alpha, r.c.eta, r.c.prism, r.sim.peak.value,
                       r.sim.energy.value, r.v[0].peak});
    return out;
}

void simulator_errors(const Row& row, const std::vector<SimConfig>& study, Result& res) {
    if (!(row.mask & 2)) return;
    // The study's prisms are the paper's cube: a canted cube or one with dihedral errors has no
    // configuration there to be compared with.
    const Params& m = row.material;
    if (m.cant_angle != 0 || m.dihedral_error != 0 || m.dihedral_spread != 0) return;
    double e2 = 0, p2 = 0, eWorst = 0, pWorst = 0;
    int n = 0;
    for (const SimConfig& c : study) {
        if (c.prism != row.material.prism_reflection) continue;
        Params p = row.material, q = row.reference;
        for (Params* x : {&p, &q}) {
            x->roughness = c.roughness;
            x->ior = c.ior;
            x->diffuse_color = {0.9, 0.9, 0.9};
        }
        const LocalEval f = row.make_eval(p);
        const PrismaticRetroreflector<double> ref(q);
        const double t = c.thetaDeg * M_PI / 180.0;
        const glm::dvec3 wi(std::sin(t), 0.0, std::cos(t));
        glm::dvec3 got[3];
        f(wi, wi, got);
        const double refPeak = ref.eval(wi, wi).f.retro.x;
        const double peakErr = refPeak > 0 ? c.modelPeak * (got[1].x / refPeak) / c.simPeak - 1 : 0;
        using Core = core<double>;
        Core::incident s;
        Core::setup(ref.core_material(), wi, s);
        const int g = 64;
        // A ring of spots (dihedral errors) adds the ring's angle to the sampling map.
        const int rings = s.ringRadius > 0 ? PrismaticRetroreflector<double>::kAlbedoRingPoints : 1;
        double energy = 0;
        for (int k = 0; k < rings; ++k)
            for (int a = 0; a < g; ++a)
                for (int b = 0; b < g; ++b) {
                    const glm::dvec3 wo =
                        Core::lobe_sample(ref.core_material(), s, wi, f64::RP_LOBE_RETRO,
                                          (a + 0.5) / g, (b + 0.5) / g, (k + 0.5) / rings);
                    if (!(wo.z >= f64::RP_MIN_COS)) continue;
                    const double pdf =
                        Core::lobe_pdf(ref.core_material(), s, wi, wo, f64::RP_LOBE_RETRO);
                    if (!(pdf > 0)) continue;
                    f(wi, wo, got);
                    energy += got[1].x * wo.z / pdf;
                }
        energy /= double(g) * g * rings;
        const double energyErr = energy / c.simEnergy - 1;
        e2 += energyErr * energyErr;
        p2 += peakErr * peakErr;
        if (std::abs(energyErr) > std::abs(eWorst)) eWorst = energyErr;
        if (std::abs(peakErr) > std::abs(pWorst)) pWorst = peakErr;
        ++n;
    }
    if (n == 0) return;
    res.simConfigs = n;
    res.simEnergyRms = std::sqrt(e2 / n);
    res.simEnergyWorst = eWorst;
    res.simPeakRms = std::sqrt(p2 / n);
    res.simPeakWorst = pWorst;
}

std::vector<GlslCost> glsl_costs() {
    const int n = 100000;
    std::vector<std::array<Vec3d, 2>> pairs;
    for (int i = 0; i < n; ++i) {
        const double t = 0.05 + 1.4 * double((i * 7919LL) % n) / n;
        const double p = 6.283 * double((i * 104729LL) % n) / n;
        const Vec3d wi = {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
        pairs.push_back(
            {wi, {-wi[0] * 0.9, -wi[1] * 0.9, std::sqrt(1.0 - 0.81 * (1.0 - wi[2] * wi[2]))}});
    }
    std::vector<GlslCost> out;
    for (const glsl::Variant& v : glsl::standard_variants()) {
        const std::string lib = embedded_variant(v.name);
        long constants = -1;
        const long instr = glsl::spirv_instructions(lib, v.name, &constants);
        gl::Runner runner(lib);
        Params p;
        if (v.era_mode >= 0) p.era_mode = v.era_mode;
        if (v.prism_reflection >= 0) p.prism_reflection = v.prism_reflection;
        if (v.fidelity >= 0) p.fidelity = v.fidelity;
        runner.evaluate(p, {pairs.begin(), pairs.begin() + 64}); // warm up
        const auto t0 = std::chrono::steady_clock::now();
        runner.evaluate(p, pairs);
        const double secs =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        out.push_back({v.name, instr, constants, n / secs});
    }
    return out;
}

// Relative L1 error of the node with `p` against the same node in the exact tier (double),
// over the check query set's directions (sum |f - f_exact| / sum |f_exact|).
double fidelity_error(const Params& p) {
    Params exact = p;
    exact.fidelity = 0;
    double num = 0, den = 0;
    for (Query q : check_query_set()) {
        q.material = p;
        const nlohmann::json a = answer_query(q, "cpp-double")["results"];
        q.material = exact;
        const nlohmann::json b = answer_query(q, "cpp-double")["results"];
        for (size_t i = 0; i < a.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                num += std::abs(a[i]["f"][c].get<double>() - b[i]["f"][c].get<double>());
                den += std::abs(b[i]["f"][c].get<double>());
            }
    }
    return den > 0 ? num / den : 0.0;
}

VariantChoice choose_variant(const Params& given, double maxError) {
    const Params p = sanitize(given);
    const bool hasSurface = p.specular > 0 && p.weight > 0;
    const bool hasRetro =
        (p.retro_color[0] > 0 || p.retro_color[1] > 0 || p.retro_color[2] > 0) && p.weight > 0;
    const bool hasDiffuse =
        (p.diffuse_color[0] > 0 || p.diffuse_color[1] > 0 || p.diffuse_color[2] > 0) &&
        p.weight > 0;
    Params fast = p;
    fast.fidelity = 1;
    VariantChoice out;
    out.fastError = fidelity_error(fast);
    for (const glsl::Variant& v : glsl::standard_variants()) {
        if ((hasSurface && !v.surface) || (hasRetro && !v.retro) || (hasDiffuse && !v.diffuse))
            continue;
        if (v.era_mode >= 0 && v.era_mode != p.era_mode) continue;
        if (v.prism_reflection >= 0 && v.prism_reflection != p.prism_reflection) continue;
        if (!v.canted && p.cant_angle != 0) continue;
        if (!v.dihedral && (p.dihedral_error != 0 || p.dihedral_spread != 0)) continue;
        const int fidelity = v.fidelity >= 0 ? v.fidelity : p.fidelity;
        const double error = fidelity == 1 ? out.fastError : 0.0;
        if (fidelity != p.fidelity && error > maxError) continue;
        const long cost = glsl::spirv_instructions(embedded_variant(v.name), v.name);
        out.candidates.push_back({v.name, cost, error});
        if (cost > 0 && (out.chosenCost < 0 || cost < out.chosenCost)) {
            out.chosenCost = cost;
            out.chosen = v.name;
        }
    }
    return out;
}

} // namespace retroprism::bench
