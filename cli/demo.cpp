#include "commands.h"
#include <cstdio>
namespace retroprism {
int cmd_demo(int, const char**) {
    std::fprintf(stderr, "retroprism demo: not built yet\n");
    return 1;
}
} // namespace retroprism
