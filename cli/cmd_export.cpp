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
#include "embedded_files.h"
#include "mtlx_reader.h"
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

} // namespace

int cmd_export(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism export: the MaterialX node library (rp_pbrlib) and the plain GLSL "
             "variants, for external pipelines")
        .usage("retroprism export --out DIR [--document DOC.mtlx [--material NAME] --max-error E]");
    ap.arg("--out DIR").help("folder to write (created if missing)");
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
