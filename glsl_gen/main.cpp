// retroprism_glsl_gen: writes the files generated from the core and the parameter table.
//
//   retroprism_glsl_gen SOURCE_DIR --out DIR    the build's files (run by the build):
//       DIR/glsl/<variant>.glsl    each standard variant's GLSL library;
//       DIR/glsl/mrm_ggx.glsl      the MaterialX-style retroreflective GGX baseline's library;
//       DIR/cpp/<variant>.inc      the C++ core of the variants also generated as C++;
//       DIR/embedded_files.cpp     the GLSL variants and the MaterialX library as string
//                                  literals (from glsl_gen/embedded_files.cpp.in), written last.
//   retroprism_glsl_gen SOURCE_DIR --materialx  writes the checked-in MaterialX library,
//                                               SOURCE_DIR/materialx/rp_pbrlib/, and the OSL
//                                               files (osl_gen.h): SOURCE_DIR/osl/shaders/ and
//                                               the opt-in SOURCE_DIR/materialx/rp_pbrlib_closure/.
//   retroprism_glsl_gen SOURCE_DIR --check      compares those files with what glsl_gen
//                                               generates (exit 1 on any difference).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "glsl_gen.h"
#include "osl_gen.h"

namespace {

namespace fs = std::filesystem;

// Relative path -> text.
using Files = std::vector<std::pair<std::string, std::string>>;

const char* const kUsage = "usage: retroprism_glsl_gen SOURCE_DIR (--out DIR | --materialx | "
                           "--check)\n";

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    if (!in) throw std::runtime_error(path.string() + ": cannot read");
    return ss.str();
}

// Writes through a temporary file, so that a failed run leaves no partial file behind.
void write_text(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    const fs::path tmp = path.string() + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        if (!out) throw std::runtime_error(path.string() + ": cannot write");
    }
    fs::rename(tmp, path);
}

void write_all(const fs::path& dir, const Files& files, bool verbose) {
    for (const auto& [rel, text] : files) {
        write_text(dir / rel, text);
        if (verbose) std::printf("wrote %s\n", (dir / rel).string().c_str());
    }
}

// The MaterialX library, relative to SOURCE_DIR/materialx (rp_pbrlib/...).
Files materialx_files(const std::string& root) {
    Files files = retroprism::glsl::generate_materialx(root);
    for (auto& f : files)
        f.first = fs::path(f.first).lexically_relative("materialx").string();
    return files;
}

Files variant_files(const std::string& root) {
    Files files;
    for (const auto& v : retroprism::glsl::standard_variants())
        files.push_back({"glsl/" + v.name + ".glsl", retroprism::glsl::generate_library(v, root)});
    files.push_back({"glsl/mrm_ggx.glsl", retroprism::glsl::generate_baseline_library(root)});
    for (const auto& v : retroprism::glsl::standard_variants())
        if (v.cpp)
            files.push_back(
                {"cpp/" + v.name + ".inc", retroprism::glsl::generate_cpp_core(v, root)});
    return files;
}

// The C++ source embedding `files` under their paths: the template's @RP_EXPORT_ENTRIES@
// replaced by one {path, raw string literal} entry per file.
std::string embedding_source(const std::string& tmpl, const Files& files) {
    const std::string open = "R\"RPFILE(", close = ")RPFILE\"";
    std::string entries;
    for (const auto& [rel, text] : files) {
        if (text.find(close) != std::string::npos)
            throw std::runtime_error(rel + ": holds " + close + ", the literal's delimiter");
        entries += "        {\"" + rel + "\", " + open + text + close + "},\n";
    }
    const std::string key = "@RP_EXPORT_ENTRIES@";
    const size_t at = tmpl.find(key);
    if (at == std::string::npos)
        throw std::runtime_error("glsl_gen/embedded_files.cpp.in: no " + key);
    return tmpl.substr(0, at) + entries + tmpl.substr(at + key.size());
}

void write_build_files(const std::string& root, const fs::path& out) {
    const Files variants = variant_files(root);
    write_all(out, variants, false);
    // What `retroprism export` writes: the MaterialX library and the GLSL variants.
    Files exported = materialx_files(root);
    for (const auto& f : variants)
        if (f.first.rfind("glsl/", 0) == 0) exported.push_back(f);
    const std::string tmpl = read_text(fs::path(root) / "glsl_gen" / "embedded_files.cpp.in");
    write_all(out, {{"embedded_files.cpp", embedding_source(tmpl, exported)}}, false);
    std::printf("glsl_gen: wrote %zu files to %s\n", variants.size() + 1, out.string().c_str());
}

// The number of the checked-in `files` (relative to `dir`) that differ from what glsl_gen
// generates.
int check_files(const std::string& root, const fs::path& dir, const Files& files,
                const char* what) {
    int differing = 0;
    for (const auto& [rel, text] : files) {
        const fs::path path = dir / rel;
        if (!fs::exists(path) || read_text(path) != text) {
            std::fprintf(stderr,
                         "%s: differs from what glsl_gen generates (run retroprism_glsl_gen %s "
                         "--materialx)\n",
                         path.string().c_str(), root.c_str());
            ++differing;
        }
    }
    std::printf("glsl_gen: %d of %zu %s files differ\n", differing, files.size(), what);
    return differing;
}

} // namespace

int main(int argc, char** argv) {
    const std::string mode = argc >= 3 ? argv[2] : "";
    const bool valid = (argc == 4 && mode == "--out") ||
                       (argc == 3 && (mode == "--materialx" || mode == "--check"));
    if (!valid) {
        std::fprintf(stderr, "%s", kUsage);
        return 2;
    }
    const std::string root = argv[1];
    try {
        if (mode == "--out") write_build_files(root, argv[3]);
        if (mode == "--materialx") {
            write_all(fs::path(root) / "materialx", materialx_files(root), true);
            write_all(root, retroprism::glsl::generate_osl(), true);
        }
        if (mode == "--check") {
            const int differing = check_files(root, fs::path(root) / "materialx",
                                              materialx_files(root), "MaterialX library") +
                                  check_files(root, root, retroprism::glsl::generate_osl(), "OSL");
            return differing == 0 ? 0 : 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "retroprism_glsl_gen: %s\n", e.what());
        return 1;
    }
    return 0;
}
