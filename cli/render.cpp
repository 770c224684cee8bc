// Placeholder of `retroprism render (issue 7)`, being written.
#include <cstdio>

#include "commands.h"

namespace retroprism {

int cmd_render(int, const char**) {
    std::fprintf(stderr, "retroprism render: not available yet\n");
    return 1;
}

} // namespace retroprism
