// cmd_era.cpp: `retroprism era`: the effective retroreflective area of one inner direction
// (geometry alone, no face reflectance).
#include <cmath>
#include <cstdio>
#include <string>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "error.h"
#include "parse.h"
#include "prismatic_retroreflector.h"

namespace retroprism {

int cmd_era(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism era: effective retroreflective area A of one inner direction (geometry "
             "alone, no face reflectance)")
        .usage("retroprism era --theta-t DEG [--phi DEG] [--mode averaged|matched_pair|oriented] "
               "[--cant DEG]");
    ap.arg("--theta-t DEG")
        .dest("theta_t")
        .help("polar angle of the refracted direction inside the sheet, [0, 90)");
    ap.arg("--phi DEG")
        .help("its azimuth relative to one aperture vertex (default 0)")
        .defaultval("0");
    ap.arg("--mode MODE")
        .help("averaged (default), matched_pair or oriented")
        .defaultval("averaged");
    const ParamInfo& cant = *find_param("cant_angle");
    ap.arg("--cant DEG")
        .help("cant angle of the cube corners (the node's cant_angle, default 0)")
        .defaultval("0");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    if (ap["theta_t"].get<std::string>().empty())
        throw InputError("era: --theta-t DEG is required");
    double thetaT = parse_number(ap["theta_t"].get<std::string>(), "--theta-t");
    double phi = parse_number(ap["phi"].get<std::string>(), "--phi");
    if (thetaT < 0 || thetaT >= 90) throw InputError("--theta-t: must be in [0, 90) degrees");
    const double cantDeg =
        parse_number_in(ap["cant"].get<std::string>(), "--cant", cant.min_value, cant.max_value);
    const int mode = enum_index(*find_param("era_mode"), ap["mode"].get<std::string>());
    if (mode < 0)
        throw InputError("--mode " + ap["mode"].get<std::string>() +
                         ": expected averaged, matched_pair or oriented");
    const double a = era(thetaT * M_PI / 180.0, phi * M_PI / 180.0, mode, cantDeg);
    std::printf("theta_t %.6g deg  phi %.6g deg  mode %s  cant %.6g deg  ERA %.9f\n", thetaT, phi,
                ap["mode"].get<std::string>().c_str(), cantDeg, a);
    return 0;
}

} // namespace retroprism
