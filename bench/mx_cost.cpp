// mx_cost.cpp: MaterialX's generated shaders measured as the GLSL variants are (mx_cost.h).
#include "mx_cost.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "glsl_gen.h"
#include "mx_runner.h"
#include "prismatic_retroreflector.h"
#include "text_file.h"

namespace retroprism::bench {

namespace {

namespace fs = std::filesystem;

std::string num(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", x);
    return b;
}

// Pixels per second of `shaders` rendering a 512 x 512 view of the unit square under one
// directional light from 30 degrees, after a small warm-up frame: the median of five frames.
double pixels_per_second(const gl::MxShaders& shaders, const std::string& node) {
    gl::MaterialXRunner runner(shaders, node);
    gl::MxLight light;
    light.direction = {-0.5, 0.0, -0.8660254037844386};
    const int w = 512, h = 512;
    runner.render(16, 16, {0.0, -1.0, 2.0}, 60.0, {light});
    std::vector<double> rates;
    for (int frame = 0; frame < 5; ++frame) {
        const auto t0 = std::chrono::steady_clock::now();
        runner.render(w, h, {0.0, -1.0, 2.0}, 60.0, {light});
        const double secs =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        rates.push_back(double(w) * h / secs);
    }
    std::sort(rates.begin(), rates.end());
    return rates[rates.size() / 2];
}

} // namespace

std::string mx_baseline_document() {
    const Params d;
    const std::string grey =
        num(d.diffuse_color[0]) + ", " + num(d.diffuse_color[1]) + ", " + num(d.diffuse_color[2]);
    const std::string rough = num(d.roughness) + ", " + num(d.roughness);
    return "<?xml version=\"1.0\"?>\n"
           "<materialx version=\"1.39\">\n"
           "  <dielectric_bsdf name=\"top\" type=\"BSDF\">\n"
           "    <input name=\"ior\" type=\"float\" value=\"" +
           num(d.ior) +
           "\" />\n"
           "    <input name=\"roughness\" type=\"vector2\" value=\"" +
           rough +
           "\" />\n"
           "  </dielectric_bsdf>\n"
           "  <oren_nayar_diffuse_bsdf name=\"base\" type=\"BSDF\">\n"
           "    <input name=\"color\" type=\"color3\" value=\"" +
           grey +
           "\" />\n"
           "  </oren_nayar_diffuse_bsdf>\n"
           "  <layer name=\"layered\" type=\"BSDF\">\n"
           "    <input name=\"top\" type=\"BSDF\" nodename=\"top\" />\n"
           "    <input name=\"base\" type=\"BSDF\" nodename=\"base\" />\n"
           "  </layer>\n"
           "  <surface name=\"dielectric_oren_nayar_surface\" type=\"surfaceshader\">\n"
           "    <input name=\"bsdf\" type=\"BSDF\" nodename=\"layered\" />\n"
           "  </surface>\n"
           "  <surfacematerial name=\"dielectric_oren_nayar\" type=\"material\">\n"
           "    <input name=\"surfaceshader\" type=\"surfaceshader\" "
           "nodename=\"dielectric_oren_nayar_surface\" />\n"
           "  </surfacematerial>\n"
           "</materialx>\n";
}

std::vector<MxShaderCost> mx_shader_costs(const std::string& dataDir, bool timed) {
    const fs::path dir =
        fs::temp_directory_path() / ("retroprism_mx_cost_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path nodeDoc = dir / "node.mtlx", baseDoc = dir / "baseline.mtlx";
    std::ofstream(nodeDoc) << gl::mx_query_document();
    std::ofstream(baseDoc) << mx_baseline_document();
    std::vector<MxShaderCost> out;
    try {
        gl::generate_mx_shaders(dataDir, {nodeDoc.string(), baseDoc.string()}, dir.string(),
                                {"glsl,vulkan", false});
        const struct {
            const char* material;
            const char* node;
            const char* label;
            const char* description;
        } docs[] = {{"rp_query", "rp_query_bsdf", "node",
                     "the node (default inputs) through MaterialX's surface shader"},
                    {"dielectric_oren_nayar", "top", "dielectric_oren_nayar",
                     "dielectric_bsdf (GGX) layered over oren_nayar_diffuse_bsdf"}};
        for (const auto& d : docs) {
            MxShaderCost c;
            c.material = d.label;
            c.description = d.description;
            c.spirvInstructions = glsl::spirv_instructions_of(
                read_text_file((dir / (std::string(d.material) + ".vulkan.frag")).string()), "frag",
                std::string("mx_") + d.label, &c.spirvConstants);
            if (timed)
                c.pixelsPerSecond =
                    pixels_per_second(gl::read_mx_shaders(dir.string(), d.material), d.node);
            out.push_back(c);
        }
    } catch (...) {
        fs::remove_all(dir);
        throw;
    }
    fs::remove_all(dir);
    return out;
}

} // namespace retroprism::bench
