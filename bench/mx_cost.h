// mx_cost.h: the cost of MaterialX's own generated shaders beside the node's GLSL variants
// (`retroprism bench --glsl`): real MaterialX 1.39.4 generates, for the same scene, the surface
// shader of a document with the node (its default inputs) and of the standard-node baseline a
// MaterialX user would reach for, dielectric_bsdf (GGX) layered over oren_nayar_diffuse_bsdf
// with the node's default roughness, ior and diffuse colour; each is measured by its Vulkan
// fragment shader's SPIR-V instructions after `spirv-opt -O` and by pixels per second on this
// machine's OpenGL (llvmpipe without a GPU) rendering the same plane under one directional light.
#pragma once

#include <string>
#include <vector>

namespace retroprism::bench {

struct MxShaderCost {
    std::string material;    // "node" or "dielectric_oren_nayar"
    std::string description; // what the document holds
    long spirvInstructions = -1;
    long spirvConstants = -1; // of spirvInstructions, those declaring constants
    double pixelsPerSecond = 0;
};

// The baseline document: material "dielectric_oren_nayar".
std::string mx_baseline_document();

// Generates both documents' shaders with MaterialX (`data_dir` holds materialx/tools) and
// measures them; `timed` false leaves the pixels per second at 0 (no OpenGL compile).
std::vector<MxShaderCost> mx_shader_costs(const std::string& data_dir, bool timed = true);

} // namespace retroprism::bench
