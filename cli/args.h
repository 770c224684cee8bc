// args.h: option parsing of the commands (OpenImageIO's ArgParse, the one option parser).
#pragma once

#include <OpenImageIO/argparse.h>

namespace retroprism {

// Parses a command's options (argv[0] is the command's name); returns false, with the exit
// status in `status`, when it printed help (0) or an error (2).
bool parse_command_args(OIIO::ArgParse& ap, int argc, const char** argv, int& status);

} // namespace retroprism
