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
    std::vector<std::string> thetas;
    ap.arg("--material FILE").help("node inputs as a JSON object (default: all defaults)");
    ap.arg("--theta-i DEG...").help("incident polar angles in degrees, [0, 90)");
    ap.arg("thetas").hidden().action([&](OIIO::cspan<const char*> a) { thetas.push_back(a[0]); });
    // --theta-i takes every number that follows it: turn it into positional arguments.
    std::vector<const char*> args;
    for (int i = 0; i < argc; ++i)
        if (std::strcmp(argv[i], "--theta-i") != 0) args.push_back(argv[i]);
    int status = 0;
    if (!parse_command_args(ap, int(args.size()), args.data(), status)) return status;
    if (thetas.empty()) throw InputError("albedo: --theta-i DEG... is required");
    Params p;
    std::string file = ap["material"].get<std::string>();
    if (!file.empty()) p = params_from_json(read_json(file), file);
    std::vector<double> angles;
    for (const std::string& s : thetas) {
        double thetaI = parse_number(s, "--theta-i");
        if (thetaI < 0 || thetaI >= 90)
            throw InputError("--theta-i " + s + ": must be in [0, 90) degrees");
        angles.push_back(thetaI);
    }
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
