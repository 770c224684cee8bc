// stress.h: the adversarial sweep of a backend (`retroprism check --stress`): a deterministic
// generator of hard materials and direction pairs, every value the backend returns checked
// (stress.cpp documents what is generated and what is required). The sweep prints nothing: it
// returns a Tally per backend, which report/stress_table.h prints.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "query.h"
#include "stress_tally.h"

namespace retroprism {
namespace stress {

struct Options {
    // Evaluations per backend: at least this many (whole materials), C++ and GL backends.
    long cpp_evaluations = 10000000;
    long gl_evaluations = 1000000;
    int threads = 0; // the C++ backends' materials in parallel; 0: one thread per core
    // Every pair_stride-th direction pair of each material (offset by the material's index):
    // a smaller sweep over the same materials (the bounded test); 1 in the full sweep.
    int pair_stride = 1;
};

// The bounded sweep of `backend` (`check --stress --quick`, the ctest entry stress_ci): every
// enum/boolean combination and single-input hard value on every seventh direction pair (every
// 13th for materialx, the slowest), then random hard materials up to 1e6 evaluations for the C++
// backends and 5e5 for glsl; materialx the hard materials alone. A tenth of the full sweep's
// C++ evaluations, half of its GL ones.
Options quick_options(const std::string& backend);
// The same on every pairStride-th direction pair (at least 1): materialx's budget is still the
// hard materials alone, now at that stride.
Options quick_options(const std::string& backend, int pairStride);

// The full sweep sized by `cppEvaluations` per C++ backend (`check --stress --evaluations N`):
// GL backends get a tenth of it, as in the default Options.
Options sized_options(long cppEvaluations);

// The sweep of one backend (a name of backend_names()) under `opt`; InputError naming the known
// backends for any other name. Materials 0, 1, 2, ... of material() until the evaluation budget
// is spent.
Tally sweep_backend(const std::string& backend, const Options& opt = {});

// The size of the generator (printed above the table).
Coverage coverage();

// The materials that come before the random ones: every enum/boolean combination, then every
// single-input hard value (Coverage::combinations + Coverage::single_mutations).
long hard_material_count();

// Material number `index` of the sweep, and a label for it when `label` is not null: every
// combination of the enums and booleans; each single-input hard value, on the combinations in
// turn; then random materials whose inputs are each a hard value (probability 0.4) or a random
// in-range value.
Params material(long index, std::string* label);

// The direction pairs of material p, in the input precision of a backend (float when
// floatInputs, else double), the random ones from stream `stream` (the sweep uses the
// material's index): the same pairs for the same arguments, and the same number for every
// material.
std::vector<DirectionPair> stress_pairs(const Params& p, bool floatInputs, std::uint64_t stream);

} // namespace stress
} // namespace retroprism
