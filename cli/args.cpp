#include "args.h"

#include <cstdio>
#include <cstring>

#include "error.h"
#include "parse.h"

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

bool parse_args_with_values(OIIO::ArgParse& ap, int argc, const char** argv, const char* option,
                            std::vector<std::string>& values, bool& given, int& status) {
    // The option's values are parsed as positional arguments.
    values.clear();
    given = false;
    ap.arg("values").hidden().action([&](OIIO::cspan<const char*> a) { values.push_back(a[0]); });
    std::vector<const char*> args;
    for (int i = 0; i < argc; ++i) {
        const bool isOption = std::strcmp(argv[i], option) == 0;
        given = given || isOption;
        if (!isOption) args.push_back(argv[i]);
    }
    return parse_command_args(ap, int(args.size()), args.data(), status);
}

bool parse_args_with_theta_i(OIIO::ArgParse& ap, int argc, const char** argv,
                             std::vector<double>& thetaI, int& status) {
    std::vector<std::string> values;
    bool given = false;
    if (!parse_args_with_values(ap, argc, argv, "--theta-i", values, given, status)) return false;
    if (values.empty()) throw InputError(std::string(argv[0]) + ": --theta-i DEG... is required");
    thetaI.clear();
    for (const std::string& s : values) {
        const double t = parse_number(s, "--theta-i");
        if (t < 0 || t >= 90) throw InputError("--theta-i " + s + ": must be in [0, 90) degrees");
        thetaI.push_back(t);
    }
    return true;
}

} // namespace retroprism
