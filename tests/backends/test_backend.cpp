// [backend]: every backend against the C++ double reference, through one fixture over the
// deterministic query set and the tolerance contract of cli/check.h; every input matters to
// every backend, and to the approximation materialx-portable all but its listed exceptions;
// that approximation's R_A accuracy on the bundled sheetings.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include "approximation.h"
#include "check.h"
#include "photometry.h"
#include "portable.h"

using namespace retroprism;

TEST_CASE("Every backend meets the tolerance contract against cpp-double", "[backend]") {
    const std::string backend = GENERATE(from_range(backend_names()));
    INFO("backend " << backend);
    const ToleranceContract contract;
    const CheckReport r = check_backend(backend, contract);
    std::printf("MEASURED: backend %s: %ld samples (%ld values), max err %.3g (contract), max "
                "relative %.3g, median %.3g, %ld samples above %.0e\n",
                backend.c_str(), r.samples, r.values, r.max_err, r.max_rel, r.median_err,
                r.failures, contract.per_sample);
    INFO("worst: " << r.worst);
    CHECK(r.samples > 10000);
    CHECK(double(r.failures) <= contract.allowed_fraction * double(r.samples));
    CHECK(r.max_err <= contract.hard_max);
    CHECK(r.passed);
    if (backend == "cpp-double") CHECK(r.max_err == 0.0); // the reference against itself
}

TEST_CASE("The contract catches a wrong backend", "[backend]") {
    // A backend that is off by 1e-3 in one lobe must fail: evaluate the query set with a
    // retro_color scaled by 0.999 (1.001 would be clamped back to 1) and measure it with the
    // same comparison.
    std::vector<Query> queries = check_query_set();
    long compared = 0, over = 0;
    for (Query q : queries) {
        const nlohmann::json ref = answer_query(q, "cpp-double")["results"];
        for (double& c : q.material.retro_color)
            c *= 0.999;
        const nlohmann::json bad = answer_query(q, "cpp-double")["results"];
        for (size_t i = 0; i < ref.size(); ++i) {
            double r = ref[i]["retro"][0].get<double>(), b = bad[i]["retro"][0].get<double>();
            if (r > 0) {
                ++compared;
                over += std::abs(b - r) / r > ToleranceContract().per_sample;
            }
        }
    }
    CHECK(compared > 1000);
    CHECK(over == compared);
}

namespace {

// For each input, a material where it matters and a second value for it.
struct Variation {
    std::function<void(Params&)> base;
    std::function<void(Params&)> alt;
};

const std::map<std::string, Variation>& variations() {
    static const std::map<std::string, Variation> v = {
        {"weight", {[](Params&) {}, [](Params& p) { p.weight = 0.5; }}},
        {"diffuse_color",
         {[](Params&) {},
          [](Params& p) {
              p.diffuse_color = {0.2, 0.5, 0.9};
          }}},
        {"retro_color",
         {[](Params&) {},
          [](Params& p) {
              p.retro_color = {0.5, 0.2, 1.0};
          }}},
        {"specular", {[](Params&) {}, [](Params& p) { p.specular = 0.3; }}},
        {"roughness", {[](Params&) {}, [](Params& p) { p.roughness = 0.2; }}},
        {"ior", {[](Params&) {}, [](Params& p) { p.ior = 1.6; }}},
        {"prism_reflection", {[](Params&) {}, [](Params& p) { p.prism_reflection = 1; }}},
        {"metal_reflectance",
         {[](Params& p) { p.prism_reflection = 2; }, [](Params& p) { p.metal_reflectance = 0.6; }}},
        {"era_mode", {[](Params&) {}, [](Params& p) { p.era_mode = 2; }}},
        {"orientation",
         {[](Params& p) { p.era_mode = 2; }, [](Params& p) { p.orientation = 30.0; }}},
        {"cant_angle", {[](Params&) {}, [](Params& p) { p.cant_angle = 15.0; }}},
        {"dihedral_error", {[](Params&) {}, [](Params& p) { p.dihedral_error = 10.0; }}},
        {"dihedral_spread", {[](Params&) {}, [](Params& p) { p.dihedral_spread = 10.0; }}},
        {"prism_pitch", {[](Params&) {}, [](Params& p) { p.prism_pitch = 100.0; }}},
        {"abbe_number",
         {[](Params& p) { p.wavelength = 450.0; }, [](Params& p) { p.abbe_number = 30.0; }}},
        {"wavelength",
         {[](Params& p) { p.prism_pitch = 100.0; }, [](Params& p) { p.wavelength = 1550.0; }}},
        {"retro_lobe", {[](Params&) {}, [](Params& p) { p.retro_lobe = 1; }}},
        {"reciprocal", {[](Params&) {}, [](Params& p) { p.reciprocal = true; }}},
        {"fidelity", {[](Params& p) { p.roughness = 0.3; }, [](Params& p) { p.fidelity = 1; }}},
        {"normal",
         {[](Params&) {},
          [](Params& p) {
              p.normal = {0.2, 0.0, 1.0};
          }}},
        {"tangent",
         {[](Params& p) { p.era_mode = 2; },
          [](Params& p) {
              p.tangent = {0.0, 1.0, 0.0};
          }}},
    };
    return v;
}

std::vector<DirectionPair> variation_pairs() {
    std::vector<DirectionPair> out;
    auto dir = [](double t, double p) {
        t *= M_PI / 180;
        p *= M_PI / 180;
        return Vec3d{std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
    };
    for (double ti : {0.0, 25.0, 50.0, 70.0})
        for (double pi : {0.0, 40.0}) {
            const Vec3d wi = dir(ti, pi);
            std::vector<Vec3d> wos = {wi,
                                      {-wi[0], -wi[1], wi[2]},
                                      dir(ti + 3, pi),
                                      dir(ti, pi + 4),
                                      dir(10, 200),
                                      dir(45, 100),
                                      dir(80, 300)};
            for (const Vec3d& wo : wos)
                out.push_back({wi, wo});
        }
    return out;
}

// Whether varying the input `info` alone (variations()) changes some lobe value of `backend` by
// more than 1e-3 relative (ten times the tolerance contract's per-value bound, so that a change
// is no rounding).
bool input_changes(const std::string& backend, const ParamInfo& info) {
    auto it = variations().find(info.name);
    REQUIRE(it != variations().end()); // a new input needs its variation here
    Query a, b;
    it->second.base(a.material);
    b.material = a.material;
    it->second.alt(b.material);
    a.samples = b.samples = variation_pairs();
    const nlohmann::json ra = answer_query(a, backend)["results"];
    const nlohmann::json rb = answer_query(b, backend)["results"];
    for (size_t i = 0; i < ra.size(); ++i)
        for (const char* key : {"surface", "retro", "diffuse"})
            for (int c = 0; c < 3; ++c) {
                const double x = ra[i][key][c].get<double>(), y = rb[i][key][c].get<double>();
                if (std::abs(x - y) > 1e-3 * std::max(std::abs(x), std::abs(y)) &&
                    std::max(std::abs(x), std::abs(y)) > 1e-9)
                    return true;
            }
    return false;
}

// A retro lobe at least as wide as the R_A table's largest observation angle, 1.5 degrees, at
// normal incidence (alpha_o = sqrt2 (eta - 1) alpha): where the portable graph's GGX lobe, fitted
// to the Beckmann one within 1/e of its peak, stands for it.
bool wide_retro_lobe(const Params& p) {
    return std::sqrt(2.0) * (p.ior - 1) * p.roughness >= 1.5 * M_PI / 180;
}

// The portable graph's R_A table (rotation 0) against the C++ reference's for material p.
RaDeviation portable_ra_deviation(const Params& p) {
    const Params local = ra_params(p);
    return ra_deviation(
        ra_table(p, 0.0),
        ra_table([&](const auto& dirs) { return backend_f("materialx-portable", local, dirs); },
                 0.0));
}

} // namespace

TEST_CASE("Every input changes every backend's output when varied alone", "[backend]") {
    const std::string backend = GENERATE(from_range(backend_names()));
    INFO("backend " << backend);
    int inputs = 0;
    for (const ParamInfo& info : param_table()) {
        INFO("input " << info.name);
        const bool changed = input_changes(backend, info);
        CHECK(changed);
        inputs += changed;
    }
    std::printf("MEASURED: backend %s: %d of %zu inputs change the output when varied alone\n",
                backend.c_str(), inputs, param_table().size());
}

TEST_CASE("Every input but the listed exceptions changes the portable implementation's output",
          "[backend]") {
    // The exceptions (glsl_gen/portable.h, docs/portable.md) must not change it either: the list
    // is what the portable graph does not honour, no more and no less.
    const std::string backend = GENERATE(from_range(approximation_names()));
    INFO("backend " << backend);
    int inputs = 0, excepted = 0;
    for (const ParamInfo& info : param_table()) {
        INFO("input " << info.name);
        bool listed = false;
        for (const glsl::PortableException& e : glsl::portable_exceptions())
            listed = listed || e.input == info.name;
        const bool changed = input_changes(backend, info);
        CHECK(changed != listed);
        inputs += changed;
        excepted += listed;
    }
    std::printf("MEASURED: backend %s: %d of %zu inputs change the output when varied alone, "
                "%d listed as exceptions\n",
                backend.c_str(), inputs, param_table().size(), excepted);
}

TEST_CASE("The portable implementation's R_A is within 15% up to 1 degree of observation for "
          "the sheetings with wide lobes",
          "[backend]") {
    // The target of the portable implementation (docs/portable.md): R_A within 15% of the C++
    // reference at every standard entry, for the bundled sheetings with ideal prisms, with
    // uncoated prisms in their own ERA mode (matched pairs: the graph's closed form) and with
    // uncoated prisms and the averaged ERA (the graph's fit). It holds where the graph's
    // approximations hold: a retro lobe at least as wide as the table's largest observation
    // angle, 1.5 degrees (the GGX lobe that stands for the Beckmann one is fitted within 1/e of
    // the peak; beyond, its tails are far heavier), which excludes the DG983 preset (roughness
    // 0.0078: alpha_o = 0.44 degrees at normal incidence); and observation angles up to 1
    // degree. The graph evaluates E and the cosine at the view direction, not at the light's:
    // at entrance 45 degrees E falls 3.4% per degree (ideal prisms) to 6.9% (uncoated,
    // averaged), so the table's 1.5 degrees adds 5% to 10% to the lobe fit's 3% and the other
    // factors taken at V (docs/portable.md, "Known limits"): there the test guards the measured
    // state (largest 19.9%, uncoated prisms averaged) at 20%, not the target.
    int measured = 0;
    for (const NamedMaterial& s : bundled_sheetings()) {
        const Params& p = s.params;
        if (!wide_retro_lobe(p)) continue;
        INFO(s.name);
        const RaDeviation d = portable_ra_deviation(p);
        double within1 = 0;
        for (size_t i = 0; i < d.relative.size(); ++i)
            if (ra_observation_angles()[i] <= 1.0)
                for (double r : d.relative[i])
                    within1 = std::max(within1, std::abs(r));
        std::printf("MEASURED: materialx-portable, %s: largest R_A deviation %.1f%% to 1 degree "
                    "of observation, %.1f%% in all (observation %.2f, entrance %.0f deg)\n",
                    s.name.c_str(), 100 * within1, 100 * d.max_abs, d.observation, d.entrance);
        CHECK(within1 <= 0.15);
        CHECK(d.max_abs <= 0.20);
        ++measured;
    }
    CHECK(measured >= 15);
}

TEST_CASE("The portable implementation's diffraction lobes hold R_A of the sheetings with a "
          "prism pitch within a factor 2.5",
          "[backend]") {
    // The graph's two GGX lobes per prism kind, fitted to the node's pattern at normal incidence
    // within 0.32 in ln (ideal faces; "The portable graph's diffraction lobes ..." in [glsl]),
    // widened off normal incidence by the aperture's shrinking: what stays beyond the fit is
    // the GGX lobe's own tail, which the geometric lobe's width widens (the graph adds widths in
    // quadrature, the node convolves a Gaussian), the uncoated prisms' coherence changing with
    // the incidence (the node's table, which the graph holds at normal incidence) and the cant,
    // which the fit leaves at 0. Measured largest deviation 146% (microprismatic_160um, ideal
    // faces, 1 degree, entrance -4; with one Gaussian core alone 487%): the bound 150% guards it.
    int measured = 0;
    for (const NamedMaterial& s : bundled_sheetings()) {
        const Params& p = s.params;
        if (!(p.prism_pitch > 0)) continue;
        INFO(s.name);
        const RaDeviation d = portable_ra_deviation(p);
        std::printf("MEASURED: materialx-portable, %s (prism pitch %g um): largest R_A deviation "
                    "%.1f%% (observation %.2f, entrance %.0f deg)\n",
                    s.name.c_str(), p.prism_pitch, 100 * d.max_abs, d.observation, d.entrance);
        CHECK(d.max_abs <= 1.5);
        ++measured;
    }
    CHECK(measured >= 4);
}

TEST_CASE("The portable implementation's retro lobe has the node's widths along and across the "
          "plane of incidence",
          "[backend]") {
    // retro_lobe anisotropic: alpha_par along the plane of incidence and alpha_perp across it (at
    // entrance 45 degrees alpha_par = 1.41 alpha_perp); isotropic: alpha_o both ways. The graph's
    // GGX lobe about V takes them along its tangent in the plane of incidence and across. The
    // shape test: at entrance 45 degrees, the retro lobe's values at wo turned from wi by gamma
    // within the plane of incidence (toward and away from the normal: their sum cancels the
    // first-order error of the factors the graph evaluates at V) over those at wo turned by
    // gamma across it, for gamma the node's alpha_perp there (the lobe at exp(-1) across).
    // The node's ratio is exp(1 - alpha_perp^2 / alpha_par^2) = 1.65 anisotropic, 1 isotropic;
    // the graph's must be within 10% of it (the GGX fit's 3.1% on each of four values, and the
    // second-order terms at V). With the axes swapped the graph gives 0.65 to 0.70.
    const double theta = 45 * M_PI / 180;
    const glm::dvec3 wi(std::sin(theta), 0, std::cos(theta));
    int measured = 0;
    for (const NamedMaterial& s : bundled_sheetings()) {
        Params p = s.params;
        if (!wide_retro_lobe(p) || p.prism_reflection != 0) continue;
        const double sinT = std::sin(theta) / p.ior, cosT = std::sqrt(1 - sinT * sinT);
        const double gamma =
            std::sqrt(2.0) * p.roughness * (p.ior * cosT - std::cos(theta)); // alpha_perp
        std::vector<DirectionPair> pairs;
        for (double sign : {1.0, -1.0}) {
            const glm::dvec3 along(std::sin(theta + sign * gamma), 0,
                                   std::cos(theta + sign * gamma));
            const glm::dvec3 across =
                std::cos(gamma) * wi + sign * std::sin(gamma) * glm::dvec3(0, 1, 0);
            pairs.push_back({{wi.x, wi.y, wi.z}, {along.x, along.y, along.z}});
            pairs.push_back({{wi.x, wi.y, wi.z}, {across.x, across.y, across.z}});
        }
        for (int lobe : {0, 1}) {
            p.retro_lobe = lobe;
            INFO(s.name << ", retro_lobe " << lobe);
            auto ratio = [&](const std::vector<BackendResult>& r) {
                return (r[0].retro[0] + r[2].retro[0]) / (r[1].retro[0] + r[3].retro[0]);
            };
            const double ref = ratio(evaluate_node<double>(p, pairs));
            const double got = ratio(backend("materialx-portable").evaluate(p, pairs));
            std::printf("MEASURED: materialx-portable, %s, retro_lobe %s: retro lobe along / "
                        "across the plane of incidence at entrance 45 deg %.3f (node %.3f)\n",
                        s.name.c_str(), lobe ? "anisotropic" : "isotropic", got, ref);
            CHECK(std::abs(got / ref - 1) <= 0.10);
            ++measured;
        }
    }
    CHECK(measured >= 10);
}

TEST_CASE("The portable implementation's E of matched pairs and single prisms is the node's at "
          "the retro peak",
          "[backend]") {
    // At wi = wo every factor the graph evaluates at V is the node's at wi, so between two
    // materials that differ only in prism_reflection and era_mode the graph's retro and diffuse
    // lobes must change as the node's do. Normalised by the same material with ideal prisms, the
    // averaged ERA and no cant (the graph's fit of A), the ratio portable / node of the
    // matched-pair and single-prism E (closed form in the graph) is 1 to the normaliser's fit
    // error and single-precision rounding: any error in the frame, the prisms' orientation, the
    // cant's face normals, the faces' Fresnel or the metallised substrate term shows as a ratio
    // off 1. Tolerance 1%: the fit of A is within 0.014 absolute over every cant, and within
    // 0.5% relative of A and 0.8% of 1 - A at these angles without cant (measured: the ratios of
    // the cant-0 materials, whose E is the normaliser's own A in the ideal averaged case).
    std::vector<DirectionPair> pairs;
    for (double theta : {8.0, 25.0, 40.0})
        for (double phi : {0.0, 50.0, 100.0, 215.0, 300.0}) {
            const double t = theta * M_PI / 180, f = phi * M_PI / 180;
            const std::array<double, 3> w{std::sin(t) * std::cos(f), std::sin(t) * std::sin(f),
                                          std::cos(t)};
            pairs.push_back({w, w});
        }
    double worst = 0;
    int compared = 0;
    for (double cant : {0.0, -11.0, 20.0})
        for (double orientation : {0.0, 37.0})
            for (int prism : {0, 1, 2}) {
                Params base;
                base.roughness = 0.1;
                base.ior = 1.49;
                base.cant_angle = cant;
                base.orientation = orientation;
                base.metal_reflectance = 0.8;
                Params norm = base;
                norm.era_mode = 0;
                norm.prism_reflection = 0;
                norm.cant_angle = 0;
                const auto refNorm = evaluate_node<double>(norm, pairs);
                const auto gotNorm = backend("materialx-portable").evaluate(norm, pairs);
                for (int mode : {1, 2}) {
                    Params p = base;
                    p.era_mode = mode;
                    p.prism_reflection = prism;
                    const auto ref = evaluate_node<double>(p, pairs);
                    const auto got = backend("materialx-portable").evaluate(p, pairs);
                    for (size_t i = 0; i < pairs.size(); ++i) {
                        INFO("cant " << cant << ", orientation " << orientation << ", prism "
                                     << prism << ", era_mode " << mode << ", pair " << i);
                        const double n = gotNorm[i].retro[0] / refNorm[i].retro[0];
                        const double nd = gotNorm[i].diffuse[0] / refNorm[i].diffuse[0];
                        // E below 1% of the ideal average: the ratio of two small numbers.
                        if (ref[i].retro[0] > 0.01 * refNorm[i].retro[0]) {
                            const double r = got[i].retro[0] / ref[i].retro[0] / n;
                            worst = std::max(worst, std::abs(r - 1));
                            CHECK(std::abs(r - 1) <= 0.01);
                            ++compared;
                        } else {
                            CHECK(got[i].retro[0] <= 0.02 * gotNorm[i].retro[0]);
                        }
                        const double rd = got[i].diffuse[0] / ref[i].diffuse[0] / nd;
                        worst = std::max(worst, std::abs(rd - 1));
                        CHECK(std::abs(rd - 1) <= 0.01);
                    }
                }
            }
    std::printf("MEASURED: materialx-portable at the retro peak: E of matched pairs and single "
                "prisms (and the substrate's share) relative to the node's within %.2e over %d "
                "comparisons\n",
                worst, compared);
    CHECK(compared > 200);
}
