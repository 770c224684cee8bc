// cmd_check.cpp: `retroprism check`: every backend against the reference under the tolerance
// contract (backends/check.h) and every approximation's accuracy (backends/approximation.h, R_A
// tables by analysis/photometry.h), or the adversarial sweep (backends/stress.h).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <OpenImageIO/argparse.h>

#include "approximation.h"
#include "check.h"
#include "commands.h"
#include "error.h"
#include "parse.h"
#include "photometry.h"
#include "stress.h"
#include "stress_table.h"

namespace retroprism {

namespace {

// The R_A accuracy target of an approximation at every standard entry.
constexpr double kRaTarget = 0.15;

bool check_exact(const std::vector<std::string>& backends);

// An approximation's R_A table of a material: the backend at the table's direction pairs.
RaTable backend_ra_table(const std::string& name, const Params& material) {
    const Params p = ra_params(material);
    return ra_table([&](const auto& dirs) { return backend_f(name, p, dirs); }, 0.0);
}

// Prints an approximation's accuracy on the bundled sheetings: the relative L1 error per lobe
// over the standard direction pairs and the R_A deviation from the reference, the largest and
// per entry; returns how many sheetings are within kRaTarget at every entry.
int report_approximation(const std::string& name) {
    std::printf("\n%s against cpp-double on the bundled sheetings: relative L1 error per lobe "
                "over the standard direction pairs; R_A (luminance) relative deviation at "
                "observation 0.2-1.5 x entrance -4-45 deg, rotation 0\n",
                name.c_str());
    std::printf("%-26s %9s %9s %9s %9s  %12s %s\n", "sheeting", "surface", "retro", "diffuse", "f",
                "R_A max dev", "at (obs, entr)");
    const std::vector<NamedMaterial> sheetings = bundled_sheetings();
    std::vector<RaDeviation> deviations;
    int within = 0;
    for (const NamedMaterial& s : sheetings) {
        const LobeErrors e = lobe_l1_errors(name, s.params);
        const RaTable ref = ra_table(s.params, 0.0);
        const RaDeviation d = ra_deviation(ref, backend_ra_table(name, s.params));
        std::printf("%-26s %9.4f %9.4f %9.4f %9.4f  %11.1f%% (%.2f, %.0f)\n", s.name.c_str(),
                    e.surface, e.retro, e.diffuse, e.total, 100 * d.max_abs, d.observation,
                    d.entrance);
        std::fflush(stdout);
        deviations.push_back(d);
        within += d.max_abs <= kRaTarget;
    }
    for (size_t k = 0; k < sheetings.size(); ++k) {
        const RaDeviation& d = deviations[k];
        std::printf("\nR_A deviation of %s, %s (%%; rows: observation, columns: entrance)\n",
                    name.c_str(), sheetings[k].name.c_str());
        std::printf("%8s", "obs\\ent");
        for (double b : ra_entrance_angles())
            std::printf(" %7.0f", b);
        std::printf("\n");
        for (size_t i = 0; i < d.relative.size(); ++i) {
            std::printf("%8.2f", ra_observation_angles()[i]);
            for (double r : d.relative[i])
                std::printf(" %+7.1f", 100 * r);
            std::printf("\n");
        }
    }
    std::printf("\n%s: %d of %zu sheetings within %.0f%% of the reference's R_A at every "
                "entry\n",
                name.c_str(), within, sheetings.size(), 100 * kRaTarget);
    return within;
}

} // namespace

int cmd_check(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism check: every backend (or --backend NAME) against cpp-double over the "
             "deterministic query set, under the tolerance contract of backends/check.h; an "
             "approximation (materialx-portable) by its accuracy on the bundled sheetings")
        .usage("retroprism check [--backend NAME] [--stress [--quick | --evaluations N]]");
    ap.arg("--backend NAME").help("one backend only (default: all)");
    ap.arg("--stress")
        .help("the adversarial sweep instead: counts of NaN, Inf, negative values "
              "and sample/pdf inconsistencies")
        .store_true();
    ap.arg("--quick")
        .help("with --stress: the bounded sweep of the ctest entry stress_ci (a tenth of the C++ "
              "evaluations, half the GL ones)")
        .store_true();
    ap.arg("--evaluations N")
        .help("with --stress: evaluations per C++ backend (default 1e7; a GL backend gets a "
              "tenth)");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    std::vector<std::string> backends = backend_names();
    std::vector<std::string> approximations = approximation_names();
    const std::string only = ap["backend"].get<std::string>();
    if (!only.empty()) {
        const bool exact = std::count(backends.begin(), backends.end(), only) > 0;
        const bool approximate = std::count(approximations.begin(), approximations.end(), only) > 0;
        if (!exact && !approximate) backend(only); // InputError naming the backends
        backends = exact ? std::vector<std::string>{only} : std::vector<std::string>{};
        approximations = approximate ? std::vector<std::string>{only} : std::vector<std::string>{};
    }
    if (ap["stress"].get<int>()) {
        if (backends.empty()) throw InputError("--stress: " + only + " is an approximation");
        const bool quick = ap["quick"].get<int>() != 0;
        const std::string given = ap["evaluations"].get<std::string>();
        if (quick && !given.empty())
            throw InputError("--evaluations: not with --quick (the bounded sweep has its size)");
        const stress::Options sized = stress::sized_options(
            given.empty() ? stress::Options().cpp_evaluations
                          : long(parse_count(given, "--evaluations", 1, 1e12)));
        if (quick) {
            const stress::Options cpp = stress::quick_options("cpp-double");
            std::printf("size: the bounded sweep (--quick): the hard materials on every %dth "
                        "direction pair (materialx every %dth), at least %ld evaluations per C++ "
                        "backend and %ld for glsl\n",
                        cpp.pair_stride, stress::quick_options("materialx").pair_stride,
                        cpp.cpp_evaluations, stress::quick_options("glsl").gl_evaluations);
        } else {
            std::printf("size: at least %ld evaluations per C++ backend, %ld per GL backend "
                        "(--evaluations N; --quick for the bounded sweep)\n",
                        sized.cpp_evaluations, sized.gl_evaluations);
        }
        std::fflush(stdout);
        StressTable table(stress::coverage(), stdout);
        for (const std::string& b : backends)
            table.add(stress::sweep_backend(b, quick ? stress::quick_options(b) : sized));
        return table.finish() ? 0 : 1;
    }
    bool all = true;
    if (!backends.empty()) all = check_exact(backends);
    for (const std::string& a : approximations)
        report_approximation(a);
    return all ? 0 : 1;
}

namespace {

// The exact backends under the tolerance contract; whether all pass.
bool check_exact(const std::vector<std::string>& backends) {
    const ToleranceContract contract;
    std::printf("tolerance contract: per value %.0e relative (floor %.0e of the lobe's peak, plus "
                "%.0f ulps of input sensitivity), at most %.1f%% of samples above it, none above "
                "%.0e\n",
                contract.per_sample, contract.floor_fraction, contract.input_ulps,
                100 * contract.allowed_fraction, contract.hard_max);
    std::printf("%-12s %8s %8s %12s %12s %12s %9s  %s\n", "backend", "samples", "values", "max_err",
                "median_err", "max_rel", "failures", "result");
    bool all = true;
    std::vector<CheckReport> reports;
    for (const std::string& b : backends) {
        CheckReport r = check_backend(b, contract);
        std::printf("%-12s %8ld %8ld %12.3g %12.3g %12.3g %9ld  %s\n", r.backend.c_str(), r.samples,
                    r.values, r.max_err, r.median_err, r.max_rel, r.failures,
                    r.passed ? "pass" : "FAIL");
        std::fflush(stdout);
        reports.push_back(r);
        all = all && r.passed;
    }
    for (const CheckReport& r : reports)
        if (r.max_err > 0) std::printf("worst %s: %s\n", r.backend.c_str(), r.worst.c_str());
    return all;
}

} // namespace

} // namespace retroprism
