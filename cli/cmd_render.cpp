// cmd_render.cpp: `retroprism render DOC.mtlx -o OUT.exr`: the night preview of
// analysis/night_render.h written as report/night_output.h describes, then the material's R_A
// table (Y), as `retroprism ra` prints it. A document beyond the reference reader's chain (a
// graph: layers, mixes, textures) is rendered through MaterialX's own shader
// (backends/mx_night.h), without the R_A table.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include <OpenImageIO/argparse.h>

#include "color.h"
#include "display.h"
#include "commands.h"
#include "error.h"
#include "mtlx_reader.h"
#include "mx_night.h"
#include "night_output.h"
#include "night_render.h"
#include "parse.h"
#include "paths.h"
#include "photometry.h"
#include "ra_print.h"

namespace fs = std::filesystem;

namespace retroprism {

int cmd_render(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism render: a night-time preview of a MaterialX material: a diamond sign "
             "and a sphere under a headlight beside the camera (small observation angle), "
             "optionally a fill light; direct lighting. A document of the node's chain alone "
             "(surfacematerial, surface, the node with constant inputs) is rendered with the C++ "
             "reference node; any other document (layers, mixes, textures, node graphs) with "
             "the GLSL real MaterialX 1.39.4 generates for it, on OpenGL. Writes a linear EXR "
             "(RGBA and a layer per lobe where the graph allows) and a display PNG through "
             "OpenColorIO, then prints the node's R_A table (the reference renderer only)")
        .usage("retroprism render DOC.mtlx -o OUT.exr [--material NAME] [--width W --height H] "
               "[--fill] [--png OUT.png] [--exposure EV] [--view aces|standard] [--samples N] "
               "[--observation DEG] [--sign-angle DEG] [--materialx]");
    std::string doc;
    ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> a) { doc = a[0]; });
    ap.arg("-o FILE").dest("out").help("output EXR (the PNG goes beside it, same stem)");
    ap.arg("--material NAME").help("the material of the document (default: its first)");
    ap.arg("--width W").help("image width in pixels (default 960)").defaultval("960");
    ap.arg("--height H").help("image height in pixels (default 540)").defaultval("540");
    ap.arg("--fill").help("add the fill light (dusk), showing the day colour").store_true();
    ap.arg("--png FILE").help("display PNG path (default: OUT with .png)");
    ap.arg("--exposure EV").help("exposure of the PNG in stops (default -6)").defaultval("-6");
    ap.arg("--view NAME").help("PNG view transform: aces (default) or standard").defaultval("aces");
    ap.arg("--samples N").help("N x N rays per pixel (default 3)").defaultval("3");
    ap.arg("--observation DEG")
        .help("observation angle at the sign's centre, [0, 5] degrees (default 0.5)")
        .defaultval("0.5");
    ap.arg("--materialx")
        .help("render through MaterialX's GLSL even a document the C++ reference node reads")
        .store_true();
    ap.arg("--sign-angle DEG")
        .help("entrance angle of the headlight at the sign's centre, [0, 80] degrees (default 15)")
        .defaultval("15");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    const auto t0 = std::chrono::steady_clock::now();

    // Every input is checked before anything is rendered or written.
    if (doc.empty()) throw InputError("render: give a MaterialX document (.mtlx)");
    const std::string out = ap["out"].get<std::string>();
    if (out.empty()) throw InputError("render: give the output EXR with -o OUT.exr");
    const fs::path exrPath(out);
    if (exrPath.extension() != ".exr")
        throw InputError("-o " + out + ": the output must be an OpenEXR file ending in .exr");
    fs::path pngPath = ap["png"].get<std::string>();
    if (pngPath.empty()) pngPath = fs::path(exrPath).replace_extension(".png");
    if (pngPath.extension() != ".png")
        throw InputError("--png " + pngPath.string() + ": the display image must end in .png");
    for (const fs::path& p : {exrPath, pngPath}) {
        std::error_code ec;
        const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
        if (!fs::is_directory(dir, ec))
            throw InputError(p.string() + ": the folder " + dir.string() + " does not exist");
    }
    const int width = int(parse_number_in(ap["width"].get<std::string>(), "--width", 8, 8192));
    const int height = int(parse_number_in(ap["height"].get<std::string>(), "--height", 8, 8192));
    const int spp = int(parse_number_in(ap["samples"].get<std::string>(), "--samples", 1, 16));
    const double exposure =
        parse_number_in(ap["exposure"].get<std::string>(), "--exposure", -30, 30);
    const double observation =
        parse_number_in(ap["observation"].get<std::string>(), "--observation", 0, 5);
    const double signAngle =
        parse_number_in(ap["sign-angle"].get<std::string>(), "--sign-angle", 0, 80);
    const std::string view = ap["view"].get<std::string>();
    const auto& views = display_views();
    if (std::find(views.begin(), views.end(), view) == views.end())
        throw InputError("--view " + view + ": expected aces or standard");
    const bool fill = ap["fill"].get<int>() != 0;

    std::string materialName = ap["material"].get<std::string>();
    NightSettings settings;
    settings.width = width;
    settings.height = height;
    settings.spp = spp;
    settings.observationDeg = observation;
    settings.signAngleDeg = signAngle;
    settings.fill = fill;
    const MtlxOutline outline = outline_mtlx(doc);
    NightOutput output{exrPath.string(), pngPath.string(), view, exposure, doc, "", {}, fill, ""};
    Params material;
    NightImage img;
    const bool materialx = outline.graph() || ap["materialx"].get<int>() != 0;
    if (materialx) {
        const gl::MxMaterial mx = gl::generate_mx_material(data_dir(), doc, materialName);
        materialName = mx.material;
        img = gl::render_night_mx(mx, settings);
        output.inputsDescription =
            "the GLSL of MaterialX 1.39.4 for the document (" +
            (outline.graph() ? outline.graph_description() : std::string("the node's chain")) +
            "), see retroprism render --help";
    } else {
        material = document_params(doc, materialName, &materialName);
        img = render_night(material, settings);
        output.inputs = material;
    }
    output.material = materialName;
    if (img.anomalies > 0)
        throw std::runtime_error("the shading returned " + std::to_string(img.anomalies) +
                                 " NaN, infinite or negative values; nothing written");
    write_night_images(img, output);

    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::string layers;
    for (const auto& l : night_layers(img))
        layers += std::string(layers.empty() ? "" : ", ") + l.first;
    std::printf("wrote %s (linear: R,G,B,A and layers %s)\n", exrPath.string().c_str(),
                layers.c_str());
    std::printf("wrote %s (%s)\n", pngPath.string().c_str(),
                display_description(view, exposure).c_str());
    std::printf("material \"%s\" of %s (%s): %dx%d, %d rays per pixel, %.1f s; at the sign's "
                "centre observation angle %.3f deg, entrance angle %.2f deg%s\n",
                materialName.c_str(), doc.c_str(),
                materialx ? "MaterialX's GLSL on OpenGL" : "the C++ reference node", width, height,
                spp * spp, secs, img.scene.observationAtSign, img.scene.entranceAtSign,
                fill ? ", fill light on" : "");
    if (materialx) return 0;
    std::printf("\n");
    print_ra_table(ra_table(material, 0.0), "material \"" + materialName + "\"", false, stdout);
    return 0;
}

} // namespace retroprism
