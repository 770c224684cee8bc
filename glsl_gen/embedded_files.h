// embedded_files.h: the generated files `retroprism export` writes (the MaterialX library under
// materialx/rp_pbrlib and the GLSL variants under glsl_gen/generated), embedded at build time.
#pragma once

#include <string>
#include <vector>

namespace retroprism {

struct EmbeddedFile {
    const char* path; // relative to the project root
    const char* text;
};

const std::vector<EmbeddedFile>& embedded_files();

} // namespace retroprism
