// cmd_eval.cpp: `retroprism eval`: a JSON query answered by one backend, as JSON.
#include <iostream>
#include <string>

#include <OpenImageIO/argparse.h>

#include "backend.h"
#include "commands.h"
#include "error.h"
#include "query.h"

namespace retroprism {

using nlohmann::json;

int cmd_eval(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism eval: evaluate the node at direction pairs, answered as JSON on stdout")
        .usage("retroprism eval [--backend NAME] QUERY.json|-");
    std::string file;
    ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> a) { file = a[0]; });
    ap.arg("--backend NAME").help("cpp-double (default) or cpp-float").defaultval("cpp-double");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    if (file.empty()) throw InputError("eval: give a query file, or - for standard input");
    Query q = parse_query(read_json(file), file == "-" ? "<stdin>" : file);
    json answer = answer_query(q, ap["backend"].get<std::string>());
    std::cout << answer.dump() << "\n";
    return 0;
}

} // namespace retroprism
