// Placeholder of `retroprism ra (issue 7)`, being written.
#include <cstdio>

#include "commands.h"

namespace retroprism {

int cmd_ra(int, const char**) {
    std::fprintf(stderr, "retroprism ra: not available yet\n");
    return 1;
}

} // namespace retroprism
