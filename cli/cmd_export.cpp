// cmd_export.cpp: `retroprism export` writes the node's library for use in external pipelines: the
// MaterialX node library (rp_pbrlib: nodedef, genglsl implementation and the portable nodegraph)
// and the plain GLSL variants.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "parse.h"
#include "color.h"
#include "embedded_files.h"
#include "mtlx_reader.h"
#include "openmaterial_export.h"
#include "query.h"
#include "trade.h"

namespace retroprism {

namespace {

namespace fs = std::filesystem;

const char* kReadme =
    "# retroprism export\n"
    "\n"
    "The prismatic retroreflector node for external pipelines.\n"
    "\n"
    "- `rp_pbrlib/`: a MaterialX 1.39 node library. `rp_pbrlib_defs.mtlx` defines the node\n"
    "  `rp_prismatic_retroreflector_bsdf` (nodedef `ND_rp_prismatic_retroreflector_bsdf`, a\n"
    "  reflection-only BSDF, `bsdf=\"R\"`); `genglsl/` holds its GLSL implementation\n"
    "  (`IM_rp_prismatic_retroreflector_bsdf_genglsl`, function\n"
    "  `mx_rp_prismatic_retroreflector_bsdf`), which includes MaterialX's own\n"
    "  `libraries/pbrlib/genglsl/lib/` files; `rp_pbrlib_ng.mtlx` its portable implementation,\n"
    "  the nodegraph `NG_rp_prismatic_retroreflector_bsdf` of MaterialX standard nodes.\n"
    "  MaterialX chooses, per target, an implementation of that target (GLSL, and through the\n"
    "  targets that inherit genglsl also ESSL, Vulkan GLSL and MSL: the exact node) and\n"
    "  otherwise the nodegraph (OSL and MDL: an approximation evaluated at the view direction,\n"
    "  exact at the retro peak; string inputs such as prism_reflection keep their defaults\n"
    "  there). Its approximations, accuracy and the inputs it does not honour are described in\n"
    "  the project's docs/portable.md.\n"
    "- `glsl/`: the node as plain GLSL (4.x, ESSL 3.00, Vulkan GLSL), one file per variant:\n"
    "  `prismatic_retroreflector.glsl` chooses every mode at run time; the others fix lobes,\n"
    "  ERA mode or prism reflection and leave out the code they do not use. Entry point:\n"
    "  `rp_prismatic_retroreflector_eval(inputs..., wi, wo, out surface, out retro, out diffuse,\n"
    "  out pdf)`: f in 1/sr without the cosine, per lobe. `mrm_ggx.glsl` is the comparison\n"
    "  baseline, the MaterialX-style retroreflective GGX over a Lambertian base (entry points\n"
    "  `rp_mrm_lobes`, `rp_mrm_lobes_in_frame`), which MaterialX 1.39.4 cannot generate.\n"
    "\n"
    "## Pointing MaterialX at the library\n"
    "\n"
    "Put this folder on MaterialX's search path next to MaterialX's own `libraries` folder,\n"
    "and load `rp_pbrlib` with the standard libraries:\n"
    "\n"
    "```cpp\n"
    "mx::FileSearchPath searchPath = mx::getDefaultDataSearchPath();\n"
    "searchPath.append(\"/path/to/this/folder\");\n"
    "mx::DocumentPtr libraries = mx::createDocument();\n"
    "mx::loadLibraries({\"libraries\", \"rp_pbrlib\"}, searchPath, libraries);\n"
    "// code generation: the implementation's file is found through the same path\n"
    "context.registerSourceCodeSearchPath(searchPath);\n"
    "```\n"
    "\n"
    "In Python: `mx.loadLibraries(['libraries', 'rp_pbrlib'], searchPath, libraries)`. With the\n"
    "MaterialX viewer or command-line tools: `--library rp_pbrlib --path /path/to/this/folder`.\n"
    "A document then uses the node like any BSDF:\n"
    "\n"
    "```xml\n"
    "<rp_prismatic_retroreflector_bsdf name=\"sheet\" type=\"BSDF\">\n"
    "  <input name=\"roughness\" type=\"float\" value=\"0.05\"/>\n"
    "</rp_prismatic_retroreflector_bsdf>\n"
    "<surface name=\"sheet_surface\" type=\"surfaceshader\">\n"
    "  <input name=\"bsdf\" type=\"BSDF\" nodename=\"sheet\"/>\n"
    "</surface>\n"
    "```\n";

// Writes `text` to `path` through a temporary file, so that no partial file is left.
void write_file(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    const fs::path tmp = path.string() + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        if (!out) throw InputError(path.string() + ": cannot write");
    }
    fs::rename(tmp, path);
}

// The choice of bench/trade.h, printed: the fast tier's error, each candidate and the chosen.
std::string print_variant_choice(const Params& p, double maxError) {
    const bench::VariantChoice c = bench::choose_variant(p, maxError);
    std::printf("material: fast tier error %.3g (relative L1 against exact, %s)\n", c.fastError,
                c.fastError <= maxError ? "within --max-error" : "above --max-error");
    for (const bench::VariantCandidate& v : c.candidates)
        std::printf("  candidate %-50s SPIR-V %6ld  error %.3g\n", v.variant.c_str(),
                    v.spirvInstructions, v.error);
    if (c.chosen.empty()) throw InputError("export: no generated variant fits the material");
    std::printf("chosen: %s (SPIR-V %ld instructions)\n", c.chosen.c_str(), c.chosenCost);
    return c.chosen;
}

// `export --format openmaterial`: the material's OpenMATERIAL files, read back and checked.
int export_openmaterial(OIIO::ArgParse& ap, const fs::path& dir) {
    const std::string json = ap["json"].get<std::string>();
    const std::string document = ap["document"].get<std::string>();
    if (json.empty() == document.empty())
        throw InputError("export --format openmaterial: give the material as --json FILE.json or "
                         "--document DOC.mtlx [--material NAME]");
    OpenMaterialExport e;
    Params p;
    if (!json.empty()) {
        p = params_from_json(read_json(json), json);
        e.name = fs::path(json).stem().string();
    } else {
        p = document_params(document, ap["material"].get<std::string>(), &e.name);
    }
    if (!ap["name"].get<std::string>().empty()) e.name = ap["name"].get<std::string>();
    e.wavelengths_nm =
        parse_number_list(ap["wavelength"].get<std::string>(), "--wavelength", 1e-9, 2000);
    const std::string channel = ap["channel"].get<std::string>();
    e.channel = channel == "r" ? 0 : channel == "g" ? 1 : channel == "b" ? 2 : -1;
    if (e.channel < 0) throw InputError("--channel " + channel + ": expected r, g or b");
    e.description = "Retroreflective prismatic sheeting (" + e.name +
                    "), the BRDF computed by retroprism's node.";
    const BrdfTable written = write_openmaterial(p, e, dir.string());
    const std::string tablePath = (dir / (e.name + "_brdf.xompt")).string();
    const BrdfTable back = read_brdf_table(tablePath);
    const TableCheck c = check_brdf_table(back, p, e.channel);
    std::printf("wrote %s (%zu rows) and %s\n", tablePath.c_str(), written.rows.size(),
                (dir / (e.name + ".xomp")).string().c_str());
    std::printf("read back: %zu rows, largest relative difference from the node %.2e; linear "
                "interpolation at %zu cell centres near the retro direction: median %.2e, 90th "
                "percentile %.2e, largest %.2e\n",
                c.rows, c.max_row_error, c.centres, c.median_centre_error, c.p90_centre_error,
                c.max_centre_error);
    return 0;
}

} // namespace

int cmd_export(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism export: the MaterialX node library (rp_pbrlib) and the plain GLSL "
             "variants, for external pipelines")
        .usage("retroprism export --out DIR [--document DOC.mtlx [--material NAME] --max-error E]\n"
               "       retroprism export --format openmaterial --out DIR (--json FILE.json | "
               "--document DOC.mtlx [--material NAME]) [--wavelength NM,...] [--channel r|g|b] "
               "[--name NAME]");
    ap.arg("--out DIR").help("folder to write (created if missing)");
    ap.arg("--format NAME")
        .help("materialx (default: the node library and GLSL) or openmaterial (the material's "
              "ASAM OpenMATERIAL 3D files NAME.xomp and NAME_brdf.xompt)")
        .defaultval("materialx");
    ap.arg("--json FILE.json").dest("json").help("openmaterial: the material as node inputs");
    ap.arg("--wavelength NM")
        .help("openmaterial: the table's wavelengths in nm, comma-separated (default 905,1550)")
        .defaultval("905,1550");
    ap.arg("--channel C")
        .help("openmaterial: the colour channel r, g or b (default r)")
        .defaultval("r");
    ap.arg("--name NAME").help("openmaterial: the files' stem and material name");
    ap.arg("--document DOC.mtlx")
        .dest("document")
        .help("choose the variant for this document's material");
    ap.arg("--material NAME").dest("material").help("the document's material (default: the first)");
    ap.arg("--max-error E")
        .dest("max_error")
        .help("largest relative L1 error allowed (default 0.01)")
        .defaultval("0.01");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    const std::string out = ap["out"].get<std::string>();
    if (out.empty()) throw InputError("export: --out DIR is required");
    const fs::path dir = out;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw InputError("--out " + out + ": cannot create the folder (" + ec.message() + ")");
    const std::string format = ap["format"].get<std::string>();
    if (format == "openmaterial") return export_openmaterial(ap, dir);
    if (format != "materialx")
        throw InputError("--format " + format + ": expected materialx or openmaterial");
    int written = 0;
    for (const EmbeddedFile& f : embedded_files()) {
        write_file(dir / f.path, f.text);
        ++written;
    }
    const std::string document = ap["document"].get<std::string>();
    if (!document.empty()) {
        const std::string me = ap["max_error"].get<std::string>();
        const std::optional<double> maxError = try_parse_number(me);
        if (!maxError || !(*maxError >= 0 && *maxError <= 1))
            throw InputError("--max-error " + me + ": expected a relative error in [0, 1]");
        const MtlxDocument doc = read_mtlx(document);
        const MtlxMaterial& m = select_material(doc, ap["material"].get<std::string>());
        const std::string chosen = print_variant_choice(m.params, *maxError);
        write_file(dir / "glsl" / ("selected_" + m.name + ".glsl"), embedded_variant(chosen));
        ++written;
    }
    write_file(dir / "README.md", kReadme);
    std::printf("wrote %d files and README.md to %s\n", written, dir.string().c_str());
    return 0;
}

} // namespace retroprism
