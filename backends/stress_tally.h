// stress_tally.h: what the adversarial sweep (stress.h) finds, as plain data: the counts of one
// backend's sweep and the size of the generator. Header-only and free of the backends
// themselves, so that the printer of the table (report/stress_table.h) needs nothing else.
#pragma once

#include <algorithm>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace retroprism {
namespace stress {

// The size of the sweep's generator: direction pairs per material, enum/boolean combinations,
// single-input hard values (the materials after the combinations; random hard materials follow).
struct Coverage {
    std::size_t pairs_per_material = 0;
    long combinations = 0;
    long single_mutations = 0;
};

// What one backend's sweep found.
struct Tally {
    std::string backend;
    long materials = 0;
    long evaluations = 0; // eval() calls, or (wi, wo) pairs answered by a GL backend
    long nonzero = 0;     // ... with a finite non-zero value (the sweep is not all zeros)
    long samples = 0;     // sample() calls (C++ backends)
    long nonempty = 0;    // ... that returned a direction
    long albedos = 0;     // albedo() calls (C++ backends)
    long values = 0;      // every number checked
    long nan = 0, inf = 0, negative = 0;
    // The guards of the contract: a zero, non-finite or below-horizon direction (or weight 0)
    // must give exactly zero values, a zero pdf and an empty sample.
    long guard = 0;
    // A sample whose f or pdf differs from eval / pdf at the same local direction, or from the
    // core's sample, or a non-empty sample with pdf <= 0.
    long inconsistent = 0;
    // Samples whose f or pdf differ from eval(wi, s.wo) beyond the tolerance only because the
    // frame's round trip (to_world in sample, to_local in eval) moved the direction by a few
    // ulp; at the same local direction they agree. Reported, not a failure.
    long round_trip = 0;
    double round_trip_max_rel = 0;
    double round_trip_max_ulps = 0;
    // sample() with u outside [0, 1)^3 (NaN, Inf, negative, > 1: outside the contract):
    // calls, and calls whose output has NaN, Inf or a negative value (required: none).
    long oob_samples = 0, oob_bad = 0;
    double seconds = 0;
    // Every failure by cause, with the exact inputs of the first few.
    struct Cause {
        long count = 0;
        std::vector<std::string> examples;
    };
    std::map<std::string, Cause> causes;
    std::vector<std::string> oob_examples;
    static constexpr std::size_t kMaxExamples = 3;

    // True when every count that must be zero is zero.
    bool passed() const {
        return nan == 0 && inf == 0 && negative == 0 && guard == 0 && inconsistent == 0 &&
               oob_bad == 0;
    }
    // Adds the counts of another part of the same sweep; examples up to kMaxExamples per cause.
    void add(const Tally& o) {
        materials += o.materials;
        evaluations += o.evaluations;
        nonzero += o.nonzero;
        samples += o.samples;
        nonempty += o.nonempty;
        albedos += o.albedos;
        values += o.values;
        nan += o.nan;
        inf += o.inf;
        negative += o.negative;
        guard += o.guard;
        inconsistent += o.inconsistent;
        round_trip += o.round_trip;
        round_trip_max_rel = std::max(round_trip_max_rel, o.round_trip_max_rel);
        round_trip_max_ulps = std::max(round_trip_max_ulps, o.round_trip_max_ulps);
        oob_samples += o.oob_samples;
        oob_bad += o.oob_bad;
        for (const auto& [name, c] : o.causes) {
            Cause& mine = causes[name];
            mine.count += c.count;
            for (const std::string& e : c.examples)
                if (mine.examples.size() < kMaxExamples) mine.examples.push_back(e);
        }
        for (const std::string& e : o.oob_examples)
            if (oob_examples.size() < kMaxExamples) oob_examples.push_back(e);
    }
    // Records a failure (already counted in its column) under its cause.
    void failure(const std::string& cause, const std::string& what) {
        Cause& c = causes[cause];
        ++c.count;
        if (c.examples.size() < kMaxExamples) c.examples.push_back(what);
    }
};

} // namespace stress
} // namespace retroprism
