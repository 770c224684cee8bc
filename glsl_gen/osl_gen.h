// osl_gen.h: the Open Shading Language files generated from the parameter table
// (nodes/prismatic_retroreflector_params.def), for renderers that register the node's closure
// (osl/retroprism_closure.h):
//  - osl/shaders/retroprism.h: the closure's declaration for shaders, `closure color
//    retroprism_bsdf(<every input in table order>) [[ int builtin = 1 ]]`;
//  - osl/shaders/retroprism_bsdf.osl: a surface shader exposing every input as a parameter
//    (enums as int with their names in a mapper widget, booleans as int) and Ci = the closure;
//  - materialx/rp_pbrlib_closure/: the opt-in MaterialX library, a genosl implementation of
//    ND_rp_prismatic_retroreflector_bsdf that calls the closure. Loaded beside rp_pbrlib by a
//    renderer that registered the closure, it takes precedence over the portable nodegraph
//    (MaterialX prefers an implementation for the target over a target-less nodegraph).
// OSL names: an input named like an OSL keyword (`normal`) takes the suffix `_in`.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace retroprism::glsl {

// Relative path (under the project root) -> file text.
std::vector<std::pair<std::string, std::string>> generate_osl();

// The OSL name of an input of the parameter table.
std::string osl_name(const std::string& input);

} // namespace retroprism::glsl
