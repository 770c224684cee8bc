#include "args.h"

#include <cstdio>

namespace retroprism {

bool parse_command_args(OIIO::ArgParse& ap, int argc, const char** argv, int& status) {
    ap.exit_on_error(false);
    if (ap.parse_args(argc, argv) < 0) {
        std::fprintf(stderr, "retroprism %s: %s\n", argv[0], ap.geterror().c_str());
        status = 2;
        return false;
    }
    if (ap.aborted() || ap["help"].get<int>()) {
        status = 0;
        return false;
    }
    return true;
}

} // namespace retroprism
