// retroprism export: writes the node's library for use in external pipelines: the MaterialX
// node library (rp_pbrlib: nodedef + genglsl implementation) and the plain GLSL variants.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <OpenImageIO/argparse.h>

#include "check.h"
#include "commands.h"
#include "parse.h"
#include "embedded_files.h"
#include "glsl_gen.h"
#include "mtlx_reader.h"
#include "backend.h"
#include "query.h"

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
    "  `libraries/pbrlib/genglsl/lib/` files.\n"
    "- `glsl/`: the node as plain GLSL (4.x, ESSL 3.00, Vulkan GLSL), one file per variant:\n"
    "  `prismatic_retroreflector.glsl` chooses every mode at run time; the others fix lobes,\n"
    "  ERA mode or prism reflection and leave out the code they do not use. Entry point:\n"
    "  `rp_prismatic_retroreflector_eval(inputs..., wi, wo, out surface, out retro, out diffuse,\n"
    "  out pdf)`: f in 1/sr without the cosine, per lobe.\n"
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

// Relative L1 error of the node with `p` against the same node in the exact tier (double),
// over the check query set's directions (sum |f - f_exact| / sum |f_exact|).
double fidelity_error(const Params& p) {
    Params exact = p;
    exact.fidelity = 0;
    double num = 0, den = 0;
    for (Query q : check_query_set()) {
        q.material = p;
        const nlohmann::json a = answer_query(q, "cpp-double")["results"];
        q.material = exact;
        const nlohmann::json b = answer_query(q, "cpp-double")["results"];
        for (size_t i = 0; i < a.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                num += std::abs(a[i]["f"][c].get<double>() - b[i]["f"][c].get<double>());
                den += std::abs(b[i]["f"][c].get<double>());
            }
    }
    return den > 0 ? num / den : 0.0;
}

// The cheapest generated variant for a document's material whose error stays within maxError:
// variants that fix a mode the material does not use, or leave out a lobe it has, are out;
// the fast tier's error is measured for the material; cost is the SPIR-V instruction count.
std::string choose_variant(const Params& given, double maxError) {
    const Params p = sanitize(given);
    const bool hasSurface = p.specular > 0 && p.weight > 0;
    const bool hasRetro =
        (p.retro_color[0] > 0 || p.retro_color[1] > 0 || p.retro_color[2] > 0) && p.weight > 0;
    const bool hasDiffuse =
        (p.diffuse_color[0] > 0 || p.diffuse_color[1] > 0 || p.diffuse_color[2] > 0) &&
        p.weight > 0;
    Params fast = p;
    fast.fidelity = 1;
    const double fastError = fidelity_error(fast);
    std::printf("material: fast tier error %.3g (relative L1 against exact, %s)\n", fastError,
                fastError <= maxError ? "within --max-error" : "above --max-error");
    std::string best;
    long bestCost = -1;
    for (const glsl::Variant& v : glsl::standard_variants()) {
        if ((hasSurface && !v.surface) || (hasRetro && !v.retro) || (hasDiffuse && !v.diffuse))
            continue;
        if (v.era_mode >= 0 && v.era_mode != p.era_mode) continue;
        if (v.prism_reflection >= 0 && v.prism_reflection != p.prism_reflection) continue;
        const int fidelity = v.fidelity >= 0 ? v.fidelity : p.fidelity;
        const double error = fidelity == 1 ? fastError : 0.0;
        if (fidelity != p.fidelity && error > maxError) continue;
        const long cost = glsl::spirv_instructions(embedded_variant(v.name), v.name);
        std::printf("  candidate %-50s SPIR-V %6ld  error %.3g\n", v.name.c_str(), cost, error);
        if (cost > 0 && (bestCost < 0 || cost < bestCost)) {
            bestCost = cost;
            best = v.name;
        }
    }
    if (best.empty()) throw InputError("export: no generated variant fits the material");
    std::printf("chosen: %s (SPIR-V %ld instructions)\n", best.c_str(), bestCost);
    return best;
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
        const std::string chosen = choose_variant(m.params, *maxError);
        write_file(dir / "glsl" / ("selected_" + m.name + ".glsl"), embedded_variant(chosen));
        ++written;
    }
    write_file(dir / "README.md", kReadme);
    std::printf("wrote %d files and README.md to %s\n", written, dir.string().c_str());
    return 0;
}

} // namespace retroprism
