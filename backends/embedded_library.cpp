// The full-runtime variant the glsl backend runs, from the embedded generated files.
#include "embedded_files.h"
#include "gl_runner.h"

namespace retroprism::gl {

const std::string& embedded_library() {
    static const std::string text = embedded_variant("prismatic_retroreflector");
    return text;
}

} // namespace retroprism::gl
