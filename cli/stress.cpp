// Placeholder of the adversarial sweeps (issue 8), being written.
#include "stress.h"

#include <cstdio>

namespace retroprism {

int run_stress(const std::vector<std::string>&) {
    std::fprintf(stderr, "retroprism check --stress: not available yet\n");
    return 1;
}

} // namespace retroprism
