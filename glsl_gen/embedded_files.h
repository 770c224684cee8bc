// embedded_files.h: the generated files `retroprism export` writes, embedded at build time
// (retroprism_glsl_gen --out): the MaterialX library under rp_pbrlib/, each standard GLSL
// variant as glsl/<variant>.glsl and the MaterialX-style GGX baseline as glsl/mrm_ggx.glsl.
#pragma once

#include <string>
#include <vector>

namespace retroprism {

struct EmbeddedFile {
    const char* path; // relative to the folder `retroprism export` writes
    const char* text;
};

const std::vector<EmbeddedFile>& embedded_files();

// The GLSL library of the standard variant `name` (glsl/<name>.glsl; "mrm_ggx": the baseline's);
// std::runtime_error when no such library is embedded.
std::string embedded_variant(const std::string& name);

} // namespace retroprism
