// glsl_gen.h: generation of the node's GLSL library from the single sources of truth: the math
// core (nodes/prism_core.inc, prism_special.inc, generated/prism_tables.inc) and the parameter
// table (nodes/prismatic_retroreflector_params.def). A variant fixes, at generation time, which
// lobes exist and which ERA mode and prism reflection are used; the code it leaves out is not
// in the generated text (not a runtime branch).
#pragma once

#include <set>
#include <utility>
#include <string>
#include <vector>

namespace retroprism::glsl {

struct Variant {
    std::string name;
    bool surface = true;
    bool retro = true;
    bool diffuse = true;
    int era_mode = -1;         // -1: chosen at run time by the era_mode input
    int prism_reflection = -1; // -1: chosen at run time by the prism_reflection input
    int fidelity = -1;         // -1: chosen at run time by the fidelity input
    bool canted = true;        // false: cant_angle fixed at 0 (the canted code left out)
    bool dihedral = true;      // false: dihedral_error fixed at 0 (the ring's code left out)
    bool diffraction = true;   // false: prism_pitch fixed at 0 (the diffraction code left out)
    bool cpp = false;          // also generated as C++ (cpp/<name>.inc in the build tree)
    std::string describe() const;
};

// The full runtime variant (`prismatic_retroreflector`) first, then the specialised ones. The
// build generates each (retroprism_glsl_gen --out) and embeds them (embedded_files.h).
std::vector<Variant> standard_variants();

// The features a variant keeps (the names used by "// @rp-if" regions in the core).
std::set<std::string> features(const Variant& v);

// The GLSL library of a variant (no #version line): prelude, special functions, tables, core,
// and the entry point rp_prismatic_retroreflector_eval. `source_dir` is the project root.
// Throws std::runtime_error naming the file and line of a malformed region or a non-ASCII
// character.
std::string generate_library(const Variant& v, const std::string& source_dir);

// The GLSL library of the MaterialX-style retroreflective GGX baseline (nodes/mrm_core.inc, on
// the parts of the node's core outside its "node" regions; no #version line): what the look-dev
// page renders when it shows the baseline fitted to the node's R_A table. Entry points
// rp_mrm_lobes (local frame) and rp_mrm_lobes_in_frame (the node's shading frame).
std::string generate_baseline_library(const std::string& source_dir);

// A fragment shader around a generated library for validating it with glslangValidator: the
// inputs in a uniform block, the entry point called from main.
enum class Target { Glsl450, Essl300, Vulkan };
std::string wrap_fragment(const std::string& library, Target target);
// The same around the baseline's library: its inputs in a uniform block, rp_mrm_lobes_in_frame
// called from main.
std::string wrap_baseline_fragment(const std::string& library, Target target);

// The C++ core of a variant (the common-subset source with the regions it leaves out dropped
// and its fixed modes as constants), for a namespace of its own: what the benchmarks use to
// show that a lobe or mode fixed at compile time costs nothing.
std::string generate_cpp_core(const Variant& v, const std::string& source_dir);

// The MaterialX node library, generated from the parameter table and the full variant:
// relative path (under the project root) -> file text. Node `rp_prismatic_retroreflector_bsdf`,
// nodedef ND_rp_prismatic_retroreflector_bsdf (bsdf="R"), genglsl implementation
// IM_rp_prismatic_retroreflector_bsdf_genglsl, function mx_rp_prismatic_retroreflector_bsdf.
std::vector<std::pair<std::string, std::string>> generate_materialx(const std::string& source_dir);

// The relative cost of a generated library: the instructions of its Vulkan fragment wrapper
// after `spirv-opt -O` (glslangValidator, spirv-opt and spirv-dis on the PATH; constants and
// the tables' data included), or -1 when the tools fail.
long spirv_instructions(const std::string& library, const std::string& name,
                        long* constants = nullptr);
// The instructions of a whole shader for Vulkan (`stage` as glslangValidator names it: frag,
// vert, comp) after `spirv-opt -O`, counted as above; -1 when the tools fail. `constants`, when
// given, receives how many of them declare constants (OpConstant, OpConstantComposite, ...: the
// tables' data among them), the rest being code, types and declarations.
long spirv_instructions_of(const std::string& source, const std::string& stage,
                           const std::string& name, long* constants = nullptr);

// The entry point's GLSL signature: the node inputs in table order, then the directions.
std::string entry_signature();

} // namespace retroprism::glsl
