// cmd_params.cpp: `retroprism params [--json]`: the node's inputs as a Markdown table, or as
// JSON (io/query.h, params_table_json) for the look-dev page's controls.
#include <cstdio>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "query.h"

namespace retroprism {

int cmd_params(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism params: the node's inputs (the parameter table) as a Markdown table, or "
             "as JSON")
        .usage("retroprism params [--json]");
    ap.arg("--json")
        .help("a JSON array, one object per input (type, default, range or values, "
              "doc)")
        .store_true();
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    if (ap["json"].get<int>() != 0)
        std::printf("%s\n", params_table_json().dump(2).c_str());
    else
        std::fputs(params_markdown().c_str(), stdout);
    return 0;
}

} // namespace retroprism
