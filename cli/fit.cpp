// Placeholder of `retroprism fit (issue 7)`, being written.
#include <cstdio>

#include "commands.h"

namespace retroprism {

int cmd_fit(int, const char**) {
    std::fprintf(stderr, "retroprism fit: not available yet\n");
    return 1;
}

} // namespace retroprism
