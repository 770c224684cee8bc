#include "check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "stats.h"

namespace retroprism {

using nlohmann::json;

namespace {

double to_float(double v) {
    return double(float(v));
}

Vec3d float_dir(double x, double y, double z) {
    double len = std::sqrt(x * x + y * y + z * z);
    return {to_float(x / len), to_float(y / len), to_float(z / len)};
}

Vec3d dir_deg(double thetaDeg, double phiDeg) {
    const double t = thetaDeg * M_PI / 180.0, p = phiDeg * M_PI / 180.0;
    return float_dir(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

std::vector<Params> check_materials() {
    std::vector<Params> out;
    const double roughness[] = {1e-4, 0.005, 0.05, 0.3, 1.0};
    const double ior[] = {1.0 + 1.0 / 8192.0, 1.25, 1.49, 1.586, 2.0, 3.0};
    int k = 0;
    for (int prism = 0; prism < 3; ++prism)
        for (int era = 0; era < 3; ++era)
            for (int j = 0; j < 4; ++j, ++k) {
                Params p;
                p.prism_reflection = prism;
                p.era_mode = era;
                p.roughness = to_float(roughness[(k + j) % 5]);
                p.ior = to_float(ior[(3 * k + j) % 6]);
                p.orientation = to_float(j * 37.5);
                // The paper's cube and canted ones, edge- and face-more-parallel.
                p.cant_angle = j == 0 ? 0.0 : to_float(-34.0 + 17.0 * j);
                // Perfect cube corners and ones with dihedral errors of 2 to 50 arcmin.
                p.dihedral_error = j % 2 == 0 ? 0.0 : to_float(2.0 + 6.0 * (k % 9));
                // Random dihedral errors of 1 to 25 arcmin, with and without the ring.
                p.dihedral_spread = k % 3 == 1 ? to_float(1.0 + 3.0 * (k % 9)) : 0.0;
                p.diffuse_color = {to_float(0.9), to_float(0.5 + 0.1 * j), to_float(0.05)};
                p.retro_color = {1.0, to_float(0.8), to_float(0.1 * j)};
                p.specular = j == 3 ? 0.0 : to_float(1.0 - 0.2 * j);
                p.metal_reflectance = to_float(0.7 + 0.05 * j);
                p.weight = j == 2 ? to_float(0.75) : 1.0;
                p.retro_lobe = (k / 2) % 2;
                p.reciprocal = k % 3 == 0;
                p.fidelity = (k / 3) % 2;
                if (j == 1) {
                    // A tilted frame: directions are given in the space of normal and tangent.
                    p.normal = float_dir(0.2, -0.1, 1.0);
                    p.tangent = float_dir(1.0, 0.3, 0.0);
                }
                out.push_back(p);
            }
    // The extremes of the stability tests: roughness at and below the floor, ior 1 and 3,
    // colours 0 and 1.
    for (double r : {0.0, 1e-6, 1.0})
        for (double eta : {1.0, 3.0}) {
            Params p;
            p.roughness = r;
            p.ior = eta;
            p.diffuse_color = {0.0, 1.0, 1.0};
            p.retro_color = {1.0, 0.0, 1.0};
            out.push_back(p);
        }
    return out;
}

} // namespace

std::vector<DirectionPair> standard_pairs(const Params& p) {
    std::vector<DirectionPair> samples;
    PrismaticRetroreflector<double> node(p);
    const double alpha = std::max(p.roughness, 1e-4);
    for (double thetaI : {0.0, 0.5, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.5}) {
        const double phiI = 20.0;
        const Vec3d wiL = dir_deg(thetaI, phiI);
        // Directions in the local frame, then into the parameter frame of the node.
        std::vector<Vec3d> wos = {wiL, {-wiL[0], -wiL[1], wiL[2]}, {0, 0, 1}};
        for (double s : {0.5, 1.0, 2.0, 3.0})
            for (int axis = 0; axis < 2; ++axis) {
                double dx = axis == 0 ? s * alpha : 0.0, dy = axis == 1 ? s * alpha : 0.0;
                wos.push_back(float_dir(wiL[0] + dx, wiL[1] + dy, wiL[2]));
                wos.push_back(float_dir(-wiL[0] + dx, -wiL[1] + dy, wiL[2]));
            }
        for (double thetaO : {5.0, 40.0, 70.0, 88.0, 89.99})
            for (double phiO : {0.0, 90.0, 200.0, 290.0})
                wos.push_back(dir_deg(thetaO, phiO));
        wos.push_back(dir_deg(95.0, 0.0)); // below the horizon
        auto toParent = [&](const Vec3d& l) {
            glm::dvec3 w = node.to_world(glm::dvec3(l[0], l[1], l[2]));
            return float_dir(w.x, w.y, w.z);
        };
        for (const Vec3d& wo : wos)
            samples.push_back({toParent(wiL), toParent(wo)});
    }
    return samples;
}

std::vector<Query> check_query_set() {
    std::vector<Query> queries;
    for (const Params& p : check_materials()) {
        Query q;
        q.material = p;
        q.samples = standard_pairs(p);
        queries.push_back(q);
    }
    return queries;
}

namespace {

// The compared values of a result: the three lobes (RGB) and the pdf.
const char* const kLobeNames[3] = {"surface", "retro", "diffuse"};

const std::array<double, 3>& lobe(const BackendResult& r, int k) {
    return k == 0 ? r.surface : k == 1 ? r.retro : r.diffuse;
}

// A lobe ("surface", "retro", "diffuse") or the pdf of a result as JSON, for reports.
json value_json(const BackendResult& r, const std::string& what) {
    if (what == "pdf") return std::isnan(r.pdf) ? json(nullptr) : json(r.pdf);
    for (int k = 0; k < 3; ++k)
        if (what == kLobeNames[k]) return json(lobe(r, k));
    return json(nullptr);
}

std::vector<BackendResult> reference(const Params& p, const std::vector<DirectionPair>& pairs) {
    return backend("cpp-double").evaluate(p, pairs);
}

// The reference's change when each direction of each sample is turned by one float ulp: the
// largest absolute change over the eight turns, per compared value (9 lobe channels, pdf).
std::vector<std::array<double, 10>> input_sensitivity(const Query& q) {
    const double ulp = std::ldexp(1.0, -24);
    std::vector<std::array<double, 10>> sens(q.samples.size());
    const std::vector<BackendResult> base = reference(q.material, q.samples);
    for (int dirIdx = 0; dirIdx < 2; ++dirIdx)
        for (int axis = 0; axis < 2; ++axis)
            for (int sign = -1; sign <= 1; sign += 2) {
                std::vector<DirectionPair> turned = q.samples;
                for (DirectionPair& s : turned) {
                    Vec3d& w = dirIdx == 0 ? s.wi : s.wo;
                    glm::dvec3 v(w[0], w[1], w[2]);
                    glm::dvec3 helper =
                        std::abs(v.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
                    glm::dvec3 a = glm::normalize(glm::cross(v, helper));
                    glm::dvec3 b = glm::cross(v, a);
                    glm::dvec3 t = v + double(sign) * ulp * (axis == 0 ? a : b);
                    w = {t.x, t.y, t.z};
                }
                const std::vector<BackendResult> r = reference(q.material, turned);
                for (size_t i = 0; i < sens.size(); ++i) {
                    for (int k = 0; k < 3; ++k)
                        for (int ch = 0; ch < 3; ++ch)
                            sens[i][size_t(3 * k + ch)] = std::max(
                                sens[i][size_t(3 * k + ch)],
                                std::abs(lobe(r[i], k)[size_t(ch)] - lobe(base[i], k)[size_t(ch)]));
                    sens[i][9] = std::max(sens[i][9], std::abs(r[i].pdf - base[i].pdf));
                }
            }
    return sens;
}

// The largest reference value of each lobe and of the pdf over a material's samples.
std::array<double, 4> peaks(const std::vector<BackendResult>& ref) {
    std::array<double, 4> peak = {0, 0, 0, 0};
    for (const BackendResult& r : ref) {
        for (int k = 0; k < 3; ++k)
            for (int ch = 0; ch < 3; ++ch)
                peak[size_t(k)] = std::max(peak[size_t(k)], std::abs(lobe(r, k)[size_t(ch)]));
        peak[3] = std::max(peak[3], std::abs(r.pdf));
    }
    return peak;
}

// One sample of a backend against the reference under the contract: its largest err (returned)
// and which value it was (`where`); every value's relative difference goes into rep.max_rel.
double sample_error(const BackendResult& got, const BackendResult& ref,
                    const std::array<double, 4>& peak, const std::array<double, 10>& sens,
                    const ToleranceContract& c, CheckReport& rep, std::string& where) {
    double worst = 0;
    auto compare = [&](double x, double r, double pk, double sensitivity, const char* what) {
        const double scale = std::max(std::abs(r), c.floor_fraction * pk);
        const double diff = std::abs(x - r);
        // Equal values agree whatever the scale (a lobe that is 0 for the whole material has no
        // peak); any difference at zero scale, or a non-finite value, fails.
        double rel = diff == 0 ? 0.0 : diff / scale;
        double err = diff == 0 ? 0.0 : diff / (scale + c.input_ulps * sensitivity / c.per_sample);
        if (!std::isfinite(x) || std::isnan(rel) || std::isnan(err)) err = rel = INFINITY;
        if (!(rel <= rep.max_rel)) rep.max_rel = rel;
        if (!(err <= worst)) {
            worst = err;
            where = what;
        }
        rep.values += 1;
    };
    for (int k = 0; k < 3; ++k)
        for (int ch = 0; ch < 3; ++ch)
            compare(lobe(got, k)[size_t(ch)], lobe(ref, k)[size_t(ch)], peak[size_t(k)],
                    sens[size_t(3 * k + ch)], kLobeNames[k]);
    // A backend without a pdf (MaterialX's shaders have none) answers NaN.
    if (!std::isnan(got.pdf)) compare(got.pdf, ref.pdf, peak[3], sens[9], "pdf");
    return worst;
}

} // namespace

CheckReport check_backend(const std::string& name, const ToleranceContract& c) {
    CheckReport rep;
    rep.backend = name;
    Backend& tested = backend(name);
    std::vector<double> sampleErr;
    const std::vector<Query> queries = check_query_set();
    for (size_t qi = 0; qi < queries.size(); ++qi) {
        const Query& q = queries[qi];
        const std::vector<BackendResult> ref = reference(q.material, q.samples);
        const std::vector<BackendResult> got = tested.evaluate(q.material, q.samples);
        const std::vector<std::array<double, 10>> sens = input_sensitivity(q);
        const std::array<double, 4> peak = peaks(ref);
        for (size_t i = 0; i < ref.size(); ++i) {
            std::string where;
            const double worst = sample_error(got[i], ref[i], peak, sens[i], c, rep, where);
            rep.samples += 1;
            if (worst > c.per_sample) rep.failures += 1;
            sampleErr.push_back(worst);
            if (!(worst <= rep.max_err)) {
                rep.max_err = worst;
                std::ostringstream ss;
                ss << "material " << qi << " " << params_to_json(q.material).dump() << ", sample "
                   << i << " wi " << json(q.samples[i].wi).dump() << " wo "
                   << json(q.samples[i].wo).dump() << ", " << where << ": "
                   << value_json(ref[i], where).dump() << " vs "
                   << value_json(got[i], where).dump();
                rep.worst = ss.str();
            }
        }
    }
    rep.median_err = median(sampleErr);
    rep.passed = rep.samples > 0 &&
                 double(rep.failures) <= c.allowed_fraction * double(rep.samples) &&
                 rep.max_err <= c.hard_max;
    return rep;
}

} // namespace retroprism
