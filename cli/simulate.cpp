// Placeholder of `retroprism simulate: microgeometry Monte Carlo (issue 3)`, being written.
#include <cstdio>

#include "commands.h"

namespace retroprism {

int cmd_simulate(int, const char**) {
    std::fprintf(stderr, "retroprism simulate: not available yet\n");
    return 1;
}

} // namespace retroprism
