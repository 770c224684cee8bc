// retroprism_glsl_gen: writes every generated file — glsl_gen/generated/<variant>.glsl for each
// standard variant and the MaterialX library under materialx/rp_pbrlib/ — or, with --check,
// compares them with what is checked in (exit 1 on any difference).
//
//   retroprism_glsl_gen SOURCE_DIR [--check]
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "glsl_gen.h"

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3 || (argc == 3 && std::strcmp(argv[2], "--check") != 0)) {
        std::fprintf(stderr, "usage: retroprism_glsl_gen SOURCE_DIR [--check]\n");
        return 2;
    }
    const std::string root = argv[1];
    const bool check = argc == 3;
    int differing = 0;
    size_t files = 0;
    try {
        std::vector<std::pair<std::string, std::string>> outputs;
        for (const auto& v : retroprism::glsl::standard_variants())
            outputs.push_back({"glsl_gen/generated/" + v.name + ".glsl",
                               retroprism::glsl::generate_library(v, root)});
        for (const auto& v : retroprism::glsl::standard_variants())
            if (v.cpp)
                outputs.push_back({"nodes/generated/cpp/" + v.name + ".inc",
                                   retroprism::glsl::generate_cpp_core(v, root)});
        for (auto& f : retroprism::glsl::generate_materialx(root))
            outputs.push_back(f);
        files = outputs.size();
        for (const auto& [rel, text] : outputs) {
            const std::string path = root + "/" + rel;
            if (check) {
                std::ifstream in(path, std::ios::binary);
                std::stringstream ss;
                ss << in.rdbuf();
                if (!in || ss.str() != text) {
                    std::fprintf(stderr,
                                 "%s: differs from what glsl_gen generates (run "
                                 "retroprism_glsl_gen %s)\n",
                                 path.c_str(), root.c_str());
                    ++differing;
                }
            } else {
                std::filesystem::create_directories(std::filesystem::path(path).parent_path());
                std::ofstream out(path, std::ios::binary);
                out << text;
                if (!out) throw std::runtime_error(path + ": cannot write");
                std::printf("wrote %s\n", path.c_str());
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "retroprism_glsl_gen: %s\n", e.what());
        return 1;
    }
    if (check) std::printf("glsl_gen: %d of %zu generated files differ\n", differing, files);
    return differing == 0 ? 0 : 1;
}
