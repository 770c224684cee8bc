// commands.h: the subcommands of the `retroprism` command-line tool. Each takes the
// arguments after its name (argv[0] is the subcommand) and returns the exit status.
#pragma once

#include "args.h"

namespace retroprism {

int cmd_eval(int argc, const char** argv);
int cmd_era(int argc, const char** argv);
int cmd_albedo(int argc, const char** argv);
int cmd_demo(int argc, const char** argv);
int cmd_params(int argc, const char** argv);
int cmd_check(int argc, const char** argv);
int cmd_export(int argc, const char** argv);
int cmd_bench(int argc, const char** argv);
int cmd_simulate(int argc, const char** argv);
// `simulate --wave` (cmd_simulate_wave.cpp).
int simulate_wave_command(int argc, const char** argv);
int cmd_render(int argc, const char** argv);
int cmd_ra(int argc, const char** argv);
int cmd_fit(int argc, const char** argv);
int cmd_approach(int argc, const char** argv);
int cmd_view(int argc, const char** argv);
int cmd_lidar(int argc, const char** argv);

} // namespace retroprism
