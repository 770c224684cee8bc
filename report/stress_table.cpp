#include "stress_table.h"

#include <string>

namespace retroprism {

namespace {

void print_notes(std::FILE* out, const stress::Tally& t) {
    std::fprintf(out, "%s: %.1f%% of the evaluations have a non-zero value\n", t.backend.c_str(),
                 t.evaluations ? 100.0 * double(t.nonzero) / double(t.evaluations) : 0.0);
    if (t.round_trip > 0)
        std::fprintf(out,
                     "%s: %ld samples differ from eval(wi, s.wo) only through the frame's "
                     "round trip (the local direction moved by up to %.3g ulp; up to %.3g "
                     "relative); at the same local direction they agree\n",
                     t.backend.c_str(), t.round_trip, t.round_trip_max_ulps, t.round_trip_max_rel);
    if (t.oob_samples > 0)
        std::fprintf(out,
                     "%s: u outside [0, 1)^3 (clamped by sample()): %ld samples, %ld with a "
                     "NaN, Inf or negative output (required: 0)\n",
                     t.backend.c_str(), t.oob_samples, t.oob_bad);
    for (const std::string& e : t.oob_examples)
        std::fprintf(out, "  %s\n", e.c_str());
    for (const auto& [cause, c] : t.causes) {
        std::fprintf(out, "%s FAILURES (%ld): %s\n", t.backend.c_str(), c.count, cause.c_str());
        for (const std::string& e : c.examples)
            std::fprintf(out, "  %s\n", e.c_str());
    }
}

} // namespace

StressTable::StressTable(const stress::Coverage& c, std::FILE* out) : out_(out) {
    std::fprintf(out_,
                 "adversarial sweep: %zu direction pairs per material (%ld enum/boolean "
                 "combinations, %ld single-input hard values, then random hard combinations); "
                 "required: no NaN, Inf, negative value, guard violation or inconsistency\n",
                 c.pairs_per_material, c.combinations, c.single_mutations);
    std::fprintf(out_, "%-11s %9s %12s %10s %8s %12s %7s %7s %8s %6s %12s %10s %8s  %s\n",
                 "backend", "materials", "evaluations", "samples", "albedos", "values", "NaN",
                 "Inf", "negative", "guard", "inconsistent", "round-trip", "seconds", "result");
}

void StressTable::add(const stress::Tally& t) {
    // Samples, albedos and sample consistency exist for the C++ backends only.
    const bool cpp = t.samples > 0;
    auto opt = [&](long v) { return cpp ? std::to_string(v) : std::string("-"); };
    std::fprintf(out_, "%-11s %9ld %12ld %10s %8s %12ld %7ld %7ld %8ld %6ld %12s %10s %8.1f  %s\n",
                 t.backend.c_str(), t.materials, t.evaluations, opt(t.samples).c_str(),
                 opt(t.albedos).c_str(), t.values, t.nan, t.inf, t.negative, t.guard,
                 opt(t.inconsistent).c_str(), opt(t.round_trip).c_str(), t.seconds,
                 t.passed() ? "pass" : "FAIL");
    std::fflush(out_);
    tallies_.push_back(t);
}

bool StressTable::finish() {
    bool ok = true;
    for (const stress::Tally& t : tallies_) {
        print_notes(out_, t);
        ok = ok && t.passed();
    }
    double seconds = 0;
    for (const stress::Tally& t : tallies_)
        seconds += t.seconds;
    std::fprintf(out_, "stress: %s (%zu backend%s, %.1f s)\n", ok ? "pass" : "FAIL",
                 tallies_.size(), tallies_.size() == 1 ? "" : "s", seconds);
    return ok;
}

} // namespace retroprism
