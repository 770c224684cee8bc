// cmd_check.cpp: `retroprism check`: every backend against the reference under the tolerance
// contract (backends/check.h), or the adversarial sweep (backends/stress.h).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <OpenImageIO/argparse.h>

#include "check.h"
#include "commands.h"
#include "error.h"
#include "stress.h"
#include "stress_table.h"

namespace retroprism {

int cmd_check(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism check: every backend (or --backend NAME) against cpp-double over the "
             "deterministic query set, under the tolerance contract of backends/check.h")
        .usage("retroprism check [--backend NAME]");
    ap.arg("--backend NAME").help("one backend only (default: all)");
    ap.arg("--stress")
        .help("the adversarial sweep instead: counts of NaN, Inf, negative values "
              "and sample/pdf inconsistencies")
        .store_true();
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    std::vector<std::string> backends = backend_names();
    const std::string only = ap["backend"].get<std::string>();
    if (!only.empty()) {
        if (std::find(backends.begin(), backends.end(), only) == backends.end())
            throw InputError("--backend " + only + ": unknown backend");
        backends = {only};
    }
    if (ap["stress"].get<int>()) {
        StressTable table(stress::coverage(), stdout);
        for (const std::string& b : backends)
            table.add(stress::sweep_backend(b));
        return table.finish() ? 0 : 1;
    }
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
    return all ? 0 : 1;
}

} // namespace retroprism
