// retroprism export: writes the node's library for use in external pipelines: the MaterialX
// node library (rp_pbrlib: nodedef + genglsl implementation) and the plain GLSL variants.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "embedded_files.h"
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

} // namespace

int cmd_export(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism export: the MaterialX node library (rp_pbrlib) and the plain GLSL "
             "variants, for external pipelines")
        .usage("retroprism export --out DIR");
    ap.arg("--out DIR").help("folder to write (created if missing)");
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
        const std::string rel = f.path;
        fs::path target;
        if (rel.rfind("materialx/", 0) == 0)
            target = dir / rel.substr(10);
        else if (rel.rfind("glsl_gen/generated/", 0) == 0)
            target = dir / "glsl" / rel.substr(19);
        else
            continue;
        write_file(target, f.text);
        ++written;
    }
    write_file(dir / "README.md", kReadme);
    std::printf("wrote %d files and README.md to %s\n", written, dir.string().c_str());
    return 0;
}

} // namespace retroprism
