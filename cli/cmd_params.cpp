// cmd_params.cpp: `retroprism params`: the node's inputs as a Markdown table.
#include <cstdio>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "query.h"

namespace retroprism {

int cmd_params(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism params: the node's inputs (the parameter table) as a Markdown table")
        .usage("retroprism params");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    std::fputs(params_markdown().c_str(), stdout);
    return 0;
}

} // namespace retroprism
