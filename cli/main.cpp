// retroprism: the command-line tool over the node library (a thin layer: every figure it
// prints comes from nodes/).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

#include <OpenImageIO/argparse.h>

#include "check.h"
#include "commands.h"
#include "parse.h"
#include "backend.h"
#include "query.h"
#include "stress.h"
#include "stress_table.h"

using namespace retroprism;
using nlohmann::json;

namespace {

const char* kUsage =
    "usage: retroprism COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  eval [--backend NAME] QUERY.json|-   evaluate a batch of direction pairs (JSON answer)\n"
    "  era --theta-t DEG [--phi DEG] [--mode averaged|matched_pair|oriented]\n"
    "                                      effective retroreflective area of an inner direction\n"
    "  albedo [--material FILE.json] --theta-i DEG...\n"
    "                                      per-lobe and total directional albedo\n"
    "  demo [--out DIR] [--materials DIR]  BRDF slice plots of the bundled example materials\n"
    "  params                              the node's inputs as a Markdown table\n"
    "  render DOC.mtlx -o OUT.exr [--material NAME] [--fill] ...\n"
    "                                      night preview (EXR per lobe + PNG) and R_A table\n"
    "  ra [--material FILE.json | --document DOC.mtlx [--name NAME]] [--rotation DEG] [--csv]\n"
    "                                      coefficient of retroreflection table\n"
    "  fit DATA.dat [--json] [--plot OUT.png] [--ior ETA]\n"
    "                                      fit the node and the MaterialX retro GGX to "
    "measurements\n"
    "  simulate --theta-i DEG... [--material FILE.json] [--rays N] [--out PREFIX]\n"
    "                                      microgeometry Monte Carlo: the ground-truth BRDF\n"
    "  check [--backend NAME] [--stress]   cross-check backends against cpp-double\n"
    "  export --out DIR                    the MaterialX library and GLSL for other pipelines\n"
    "  bench [--json] [--plot OUT.png]     the speed/accuracy trade table\n"
    "\n"
    "`retroprism COMMAND --help` describes a command.\n";

} // namespace

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

int cmd_era(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism era: effective retroreflective area A of one inner direction (geometry "
             "alone, no face reflectance)")
        .usage("retroprism era --theta-t DEG [--phi DEG] [--mode averaged|matched_pair|oriented]");
    ap.arg("--theta-t DEG")
        .dest("theta_t")
        .help("polar angle of the refracted direction inside the sheet, [0, 90)");
    ap.arg("--phi DEG")
        .help("its azimuth relative to one aperture vertex (default 0)")
        .defaultval("0");
    ap.arg("--mode MODE")
        .help("averaged (default), matched_pair or oriented")
        .defaultval("averaged");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    if (ap["theta_t"].get<std::string>().empty())
        throw InputError("era: --theta-t DEG is required");
    double thetaT = parse_number(ap["theta_t"].get<std::string>(), "--theta-t");
    double phi = parse_number(ap["phi"].get<std::string>(), "--phi");
    if (thetaT < 0 || thetaT >= 90) throw InputError("--theta-t: must be in [0, 90) degrees");
    Params p;
    p.era_mode = enum_index(*find_param("era_mode"), ap["mode"].get<std::string>());
    if (p.era_mode < 0)
        throw InputError("--mode " + ap["mode"].get<std::string>() +
                         ": expected averaged, matched_pair or oriented");
    f64::rp_material m = prepare_material(sanitize(p));
    m.prism_reflection = f64::RP_PRISM_IDEAL; // geometry alone
    const double t = thetaT * M_PI / 180.0, ph = phi * M_PI / 180.0;
    f64::vec3 d(std::sin(t) * std::cos(ph), std::sin(t) * std::sin(ph), -std::cos(t));
    double a = f64::rp_retro_fraction(m, d);
    std::printf("theta_t %.6g deg  phi %.6g deg  mode %s  ERA %.9f\n", thetaT, phi,
                ap["mode"].get<std::string>().c_str(), a);
    return 0;
}

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

int cmd_check(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism check: every backend (or --backend NAME) against cpp-double over the "
             "deterministic query set, under the tolerance contract of cli/check.h")
        .usage("retroprism check [--backend NAME]");
    ap.arg("--backend NAME").help("one backend only (default: all)");
    ap.arg("--stress")
        .help("the adversarial sweep instead: counts of NaN, Inf, negative values "
              "and sample/pdf inconsistencies")
        .store_true();
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    std::vector<std::string> backends = backend_names();
    const std::string only = ap["backend"].get<std::string>();
    if (!only.empty()) {
        if (std::find(backends.begin(), backends.end(), only) == backends.end())
            throw InputError("--backend " + only + ": unknown backend");
        backends = {only};
    }
    if (ap["stress"].get<int>()) {
        StressTable table(stress::coverage(), stdout);
        for (const std::string& b : backends)
            table.add(stress::sweep_backend(b));
        return table.finish() ? 0 : 1;
    }
    const ToleranceContract contract;
    std::printf("tolerance contract: per value %.0e relative (floor %.0e of the lobe's peak, plus "
                "%.0f ulps of input sensitivity), at most %.1f%% of samples above it, none above "
                "%.0e\n",
                contract.per_sample, contract.floor_fraction, contract.input_ulps,
                100 * contract.allowed_fraction, contract.hard_max);
    std::printf("%-12s %8s %8s %12s %12s %12s %9s  %s\n", "backend", "samples", "values", "max_err",
                "median_err", "max_rel", "failures", "result");
    bool all = true;
    std::vector<CheckReport> reports;
    for (const std::string& b : backends) {
        CheckReport r = check_backend(b, contract);
        std::printf("%-12s %8ld %8ld %12.3g %12.3g %12.3g %9ld  %s\n", r.backend.c_str(), r.samples,
                    r.values, r.max_err, r.median_err, r.max_rel, r.failures,
                    r.passed ? "pass" : "FAIL");
        std::fflush(stdout);
        reports.push_back(r);
        all = all && r.passed;
    }
    for (const CheckReport& r : reports)
        if (r.max_err > 0) std::printf("worst %s: %s\n", r.backend.c_str(), r.worst.c_str());
    return all ? 0 : 1;
}

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

int main(int argc, const char** argv) {
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
        std::fputs(kUsage, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const std::string cmd = argv[1];
    try {
        if (cmd == "eval") return cmd_eval(argc - 1, argv + 1);
        if (cmd == "era") return cmd_era(argc - 1, argv + 1);
        if (cmd == "albedo") return cmd_albedo(argc - 1, argv + 1);
        if (cmd == "demo") return cmd_demo(argc - 1, argv + 1);
        if (cmd == "params") return cmd_params(argc - 1, argv + 1);
        if (cmd == "check") return cmd_check(argc - 1, argv + 1);
        if (cmd == "export") return cmd_export(argc - 1, argv + 1);
        if (cmd == "bench") return cmd_bench(argc - 1, argv + 1);
        if (cmd == "simulate") return cmd_simulate(argc - 1, argv + 1);
        if (cmd == "render") return cmd_render(argc - 1, argv + 1);
        if (cmd == "ra") return cmd_ra(argc - 1, argv + 1);
        if (cmd == "fit") return cmd_fit(argc - 1, argv + 1);
    } catch (const InputError& e) {
        std::fprintf(stderr, "retroprism %s: error: %s\n", cmd.c_str(), e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "retroprism %s: error: %s\n", cmd.c_str(), e.what());
        return 1;
    }
    std::fprintf(stderr, "retroprism: unknown command '%s'\n\n%s", cmd.c_str(), kUsage);
    return 2;
}
