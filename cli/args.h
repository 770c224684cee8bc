// args.h: option parsing of the commands (OpenImageIO's ArgParse, the one option parser).
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/argparse.h>

namespace retroprism {

// Parses a command's options (argv[0] is the command's name); returns false, with the exit
// status in `status`, when it printed help (0) or an error (2).
bool parse_command_args(OIIO::ArgParse& ap, int argc, const char** argv, int& status);

// As parse_command_args, for a command whose option `option` (declared with ap.arg for the help
// text, e.g. "--merge PART...") takes every value that follows it: the command's positional
// arguments go to `values`; `given` says whether `option` is on the command line.
bool parse_args_with_values(OIIO::ArgParse& ap, int argc, const char** argv, const char* option,
                            std::vector<std::string>& values, bool& given, int& status);

// As parse_command_args, for a command whose option `--theta-i DEG...` takes every value that
// follows it (declare it with ap.arg for the help text); the values are the incident polar
// angles in degrees, each in [0, 90) (InputError "--theta-i X: must be in [0, 90) degrees"
// otherwise), and at least one is required (InputError "<command>: --theta-i DEG... is
// required").
bool parse_args_with_theta_i(OIIO::ArgParse& ap, int argc, const char** argv,
                             std::vector<double>& thetaI, int& status);

} // namespace retroprism
