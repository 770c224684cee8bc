// cmd_albedo.cpp: `retroprism albedo`: the directional albedo per lobe.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "error.h"
#include "parse.h"
#include "query.h"

namespace retroprism {

int cmd_albedo(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism albedo: directional albedo (integral of f cos theta_o) per lobe")
        .usage("retroprism albedo [--material FILE.json] --theta-i DEG...");
    ap.arg("--material FILE").help("node inputs as a JSON object (default: all defaults)");
    ap.arg("--theta-i DEG...").help("incident polar angles in degrees, [0, 90)");
    std::vector<double> angles;
    int status = 0;
    if (!parse_args_with_theta_i(ap, argc, argv, angles, status)) return status;
    Params p;
    std::string file = ap["material"].get<std::string>();
    if (!file.empty()) p = params_from_json(read_json(file), file);
    PrismaticRetroreflector<double> node(p);
    std::printf("%10s %12s %12s %12s %12s\n", "theta_i", "surface", "retro", "diffuse", "total");
    for (double thetaI : angles) {
        const double t = thetaI * M_PI / 180.0;
        auto a = node.albedo(glm::dvec3(std::sin(t), 0.0, std::cos(t)), 256);
        auto mean = [](const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; };
        std::printf("%10.4g %12.6f %12.6f %12.6f %12.6f\n", thetaI, mean(a.surface), mean(a.retro),
                    mean(a.diffuse), mean(a.total()));
    }
    std::printf(
        "(RGB channels averaged; surface and retro by 256x256 quadrature, diffuse exact)\n");
    return 0;
}

} // namespace retroprism
