// cmd_approach.cpp: `retroprism approach DOC.mtlx --table TABLE.csv --out DIR`: a sheeting
// preset (a MaterialX document fitted to an R_A table) against the MaterialX-style
// retroreflective GGX fitted to the same table (analysis/ra_fit.h): both errors on the table,
// the night preview of each at the same exposure (analysis/night_render.h) side by side, and
// the sign's luminance for a driver approaching it under low beams (analysis/approach.h):
// one lamp of a given intensity, or with --headlamps two lamps from photometric files beside
// the luminance a driver needs. Writes DIR/NAME_node.{exr,png}, DIR/NAME_mrm.{exr,png},
// DIR/NAME_night.png (the PNGs side by side) and DIR/NAME_approach.png; prints the table
// comparison and the luminance every 30 m (report/approach_report.h).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <OpenImageIO/argparse.h>

#include "approach.h"
#include "approach_plot.h"
#include "approach_report.h"
#include "color.h"
#include "commands.h"
#include "display.h"
#include "error.h"
#include "figure.h"
#include "parse.h"
#include "query.h"
#include "ra_fit.h"
#include "ra_print.h"
#include "ra_table.h"

namespace fs = std::filesystem;

namespace retroprism {

namespace {

// --headlamps LEFT[,RIGHT] and the vehicle, sign and road they are used with.
HeadlampSettings headlamp_settings(OIIO::ArgParse& ap) {
    HeadlampSettings h;
    h.vehicle = vehicle_preset(ap["vehicle"].get<std::string>());
    const SignPosition pos = sign_position(ap["sign"].get<std::string>());
    const std::string offset = ap["sign-offset"].get<std::string>(),
                      height = ap["sign-height"].get<std::string>();
    h.sign_right = offset.empty() ? default_sign_right(pos)
                                  : parse_number_in(offset, "--sign-offset", -30, 30);
    h.sign_height =
        height.empty() ? default_sign_height(pos) : parse_number_in(height, "--sign-height", 0, 20);
    h.curve_radius =
        parse_number_in(ap["curve-radius"].get<std::string>(), "--curve-radius", -1e5, 1e5);
    h.demand_cd_m2 = parse_number_in(ap["demand"].get<std::string>(), "--demand", 1e-3, 1e4);
    return h;
}

} // namespace

int cmd_approach(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism approach: a sheeting preset (a MaterialX document) against the "
             "MaterialX-style retroreflective GGX fitted to the same R_A table: their errors on "
             "the table, both night previews at the same exposure, and the sign's luminance for a "
             "driver approaching it under low beams")
        .usage("retroprism approach DOC.mtlx --table TABLE.csv --out DIR [--name NAME] "
               "[--lamp-cd CD] [--eye-above-lamp M] [--sign-right M] [--sign-up M] | --headlamps "
               "FILE[,FILE] [--vehicle car|suv|truck] [--sign shoulder|overhead] [--sign-offset M] "
               "[--sign-height M] [--curve-radius M] [--demand CD_M2]] [--width W --height H] "
               "[--samples N] [--exposure EV]");
    std::string doc;
    ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> a) { doc = a[0]; });
    ap.arg("--table FILE").help("the R_A table (CSV) the document was fitted to");
    ap.arg("--out DIR").help("output folder (created if missing)");
    ap.arg("--name NAME").help("the material of the document (default: its first)");
    ap.arg("--lamp-cd CD")
        .help("the headlamp's intensity toward the sign in cd (default 1000)")
        .defaultval("1000");
    ap.arg("--eye-above-lamp M")
        .help("the driver's eye above the headlamp in m (default 0.55: eye 1.2 m, headlamp 0.65 "
              "m, the 30 m geometry of ASTM E1710 and EN 1436)")
        .defaultval("0.55");
    ap.arg("--sign-right M")
        .help("the sign right of the headlamp in m (default 3.7)")
        .defaultval("3.7");
    ap.arg("--sign-up M").help("the sign above the headlamp in m (default 1.5)").defaultval("1.5");
    ap.arg("--headlamps FILE[,FILE]")
        .help("two low beams from photometric files (.ies, .ldt, .csv), left[,right] (one file: "
              "both lamps) in place of --lamp-cd and the lamp above");
    ap.arg("--vehicle NAME").help("with --headlamps: car, suv or truck").defaultval("car");
    ap.arg("--sign WHERE").help("with --headlamps: shoulder or overhead").defaultval("shoulder");
    ap.arg("--sign-offset M").help("the sign right of the lane's middle (default 5.5, overhead 0)");
    ap.arg("--sign-height M").help("the sign above the road (default 2.1, overhead 6.1)");
    ap.arg("--curve-radius M").help("0 straight, > 0 turning right, < 0 left").defaultval("0");
    ap.arg("--demand CD_M2").help("the luminance needed (default 2.4 cd m^-2)").defaultval("2.4");
    ap.arg("--width W").help("night preview width (default 640)").defaultval("640");
    ap.arg("--height H").help("night preview height (default 360)").defaultval("360");
    ap.arg("--samples N").help("N x N rays per pixel (default 3)").defaultval("3");
    ap.arg("--exposure EV").help("exposure of both PNGs in stops (default -10)").defaultval("-10");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    const auto t0 = std::chrono::steady_clock::now();
    if (doc.empty()) throw InputError("approach: give the preset's MaterialX document (.mtlx)");
    const std::string tableFile = ap["table"].get<std::string>(),
                      outDir = ap["out"].get<std::string>();
    if (tableFile.empty()) throw InputError("approach: give the R_A table with --table TABLE.csv");
    if (outDir.empty()) throw InputError("approach: give the output folder with --out DIR");
    const std::string lampFiles = ap["headlamps"].get<std::string>();
    ApproachSettings as;
    as.lamp_cd = parse_number_in(ap["lamp-cd"].get<std::string>(), "--lamp-cd", 1e-3, 1e6);
    as.eye_above_lamp =
        parse_number_in(ap["eye-above-lamp"].get<std::string>(), "--eye-above-lamp", 0.0, 5.0);
    as.sign_right = parse_number_in(ap["sign-right"].get<std::string>(), "--sign-right", -30, 30);
    as.sign_up = parse_number_in(ap["sign-up"].get<std::string>(), "--sign-up", -10, 30);
    NightPreview night;
    night.settings.width = int(parse_number_in(ap["width"].get<std::string>(), "--width", 8, 8192));
    night.settings.height =
        int(parse_number_in(ap["height"].get<std::string>(), "--height", 8, 8192));
    night.settings.spp = int(parse_number_in(ap["samples"].get<std::string>(), "--samples", 1, 16));
    night.exposure = parse_number_in(ap["exposure"].get<std::string>(), "--exposure", -30, 30);

    std::string name;
    const Params node = document_params(doc, ap["name"].get<std::string>(), &name);
    const RaMeasurements table = read_ra_table(tableFile);
    const HeadlampSettings hs = lampFiles.empty() ? HeadlampSettings() : headlamp_settings(ap);
    std::pair<LuminousIntensityDistribution, LuminousIntensityDistribution> lamps;
    std::vector<HeadlampPoint> ha, hb; // the node's first: every input checked before any output
    if (!lampFiles.empty()) lamps = read_headlamp_pair(lampFiles);
    if (!lampFiles.empty())
        ha = approach_headlamps(node_lobes(node), lamps.first, lamps.second, hs);
    std::error_code ec;
    fs::create_directories(outDir, ec);
    if (!fs::is_directory(outDir, ec))
        throw InputError("--out " + outDir + ": cannot create the folder");

    const RaMrmFit mrm = fit_ra_mrm(table);
    std::printf("material \"%s\" of %s and the MaterialX-style GGX (roughness %.6g, ior %.6g, "
                "specular %.6g) fitted to %s:\n",
                name.c_str(), doc.c_str(), mrm.model.roughness, mrm.model.ior, mrm.model.specular,
                tableFile.c_str());
    print_ra_comparison(
        table, {{"node", ra_node_values(node, table.entries)}, {"mrm", mrm.report.model}}, stdout);

    const fs::path dir(outDir);
    write_night_preview(node_lobes(node), night, (dir / (name + "_node.exr")).string(), doc, name,
                        node);
    write_night_preview(mrm_lobes(mrm.model), night, (dir / (name + "_mrm.exr")).string(), doc,
                        name + " (mrm)", Params());
    plot::Text text("retroprism approach");
    const std::string exposure = display_description(night.view, night.exposure);
    plot::write_png(plot::side_by_side({(dir / (name + "_node.png")).string(),
                                        (dir / (name + "_mrm.png")).string()},
                                       {"node: " + name, "MaterialX-style GGX fitted to the same "
                                                         "R_A table"},
                                       text),
                    (dir / (name + "_night.png")).string());

    std::vector<ApproachPoint> a = approach_luminance(node_lobes(node), as),
                               b = approach_luminance(mrm_lobes(mrm.model), as), need;
    std::vector<std::string> caption = {
        plot::lamp_caption(as), "R_A table: " + tableFile + "; night previews: " + exposure};
    if (!ha.empty()) {
        hb = approach_headlamps(mrm_lobes(mrm.model), lamps.first, lamps.second, hs);
        a = approach_points(ha), b = approach_points(hb), need = approach_points(ha, true);
        caption[0] = plot::headlamp_caption(hs, lampFiles);
    }
    std::vector<plot::ApproachCurve> curves = {
        {"node: " + name, plot::kLobeColor[1], a},
        {"MaterialX-style GGX fitted to the same table", plot::kLobeColor[0], b}};
    if (!need.empty()) curves.push_back({"needed (--demand)", plot::kText, need});
    plot::write_png(plot::approach_figure("Sign luminance approaching " + name +
                                              " from 300 m to 30 m under low beams",
                                          curves, caption, text),
                    (dir / (name + "_approach.png")).string());
    std::printf("wrote %s, %s\n", (dir / (name + "_night.png")).string().c_str(),
                (dir / (name + "_approach.png")).string().c_str());
    if (ha.empty())
        print_approach(a, b, stdout);
    else
        print_headlamp_approach(ha, hb, stdout);
    std::printf("done in %.1f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return 0;
}

} // namespace retroprism
