// mx_runner.h: the node as real MaterialX generates it. A document holding the node is turned
// into GLSL by MaterialX 1.39.4 (materialx/tools/mx.cjs, run with Node.js), and that vertex and
// fragment shader pair renders on OpenGL 4.5 (EGL surfaceless) into a float target.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "gl_runner.h"

namespace retroprism::gl {

// A MaterialX light for render(): a directional light travelling along `direction`, or a
// point light at `position`, with MaterialX's attenuation (distance + 1)^decay_rate.
struct MxLight {
    bool point = false;
    Vec3d direction{0, 0, -1};
    Vec3d position{0, 0, 1};
    Vec3d color{1, 1, 1};
    double intensity = 1;
    double decay_rate = 2;
};

struct MxImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgba;          // row 0 at the bottom (OpenGL's order)
    std::vector<float> positionWorld; // the fragment's world position per pixel (xyz)
};

// A 4 x 4 matrix, column-major, as OpenGL reads it.
using Mat4 = std::array<float, 16>;

// Sets MaterialX's light i (u_lightData[i]) of the current program `program`.
void mx_set_light(unsigned program, int i, const MxLight& l);
// Sets MaterialX's matrices: the world matrix and its inverse transpose the identity, and the
// view-projection matrix.
void mx_set_matrices(unsigned program, const Mat4& viewProjection);

// The GLSL vertex and fragment shaders MaterialX generates for one material.
struct MxShaders {
    std::string vertex, fragment;
};

// What generate_mx_shaders generates: the targets (comma-separated, of glsl, essl, vulkan, msl,
// osl, mdl), and whether with the portable nodegraph in place of the genglsl implementation
// (mx.cjs --portable: the library loaded without its genglsl folder).
struct MxGenerateOptions {
    std::string targets = "glsl,essl,vulkan,msl,osl,mdl";
    bool portable = false;
};

// Generates with one run of MaterialX (`node` must be on the PATH and materialx/tools installed
// with npm; the error says so otherwise) the shaders of every material of each document into
// `out_dir`: MATERIAL.TARGET.vert and .frag for glsl, essl, vulkan and msl, MATERIAL.osl and
// MATERIAL.mdl for OSL and MDL. `data_dir` holds materialx/tools (util/paths.h). GlError with
// MaterialX's messages when a document fails.
void generate_mx_shaders(const std::string& data_dir, const std::vector<std::string>& documents,
                         const std::string& out_dir, const MxGenerateOptions& options = {});
// The document of one node with its default inputs: material "rp_query", surface
// "rp_query_surface", node "rp_query_bsdf".
const char* mx_query_document();

// The GLSL pair of `material` in a folder that generate_mx_shaders wrote.
MxShaders read_mx_shaders(const std::string& dir, const std::string& material);

class MaterialXRunner {
  public:
    // Generates the shaders of a material with MaterialX (`node` must be on the PATH and
    // materialx/tools installed with npm; the error says so otherwise) and compiles them.
    // `source_dir` is the project root. Without a document, a document of one node with its
    // default inputs is used (material "rp_query", node "rp_query_bsdf"); otherwise `material`
    // of `document`, whose node is `node`. With `portable`, MaterialX's GLSL of the portable
    // nodegraph instead of the node's genglsl implementation.
    explicit MaterialXRunner(const std::string& source_dir, const std::string& document = "",
                             const std::string& material = "rp_query",
                             const std::string& node = "rp_query_bsdf", bool portable = false);
    // Compiles shaders MaterialX has generated (generate_mx_shaders) for a material whose node
    // is `node`.
    MaterialXRunner(const MxShaders& shaders, const std::string& node);
    ~MaterialXRunner();
    MaterialXRunner(const MaterialXRunner&) = delete;
    MaterialXRunner& operator=(const MaterialXRunner&) = delete;

    // The BRDF per lobe at each (wi, wo) pair, through MaterialX's surface shader: each pair is
    // rendered into a pixel of its own under a directional light from wi, seen from wo, once
    // with each lobe alone (the other lobes' weight or colour set to 0); the response
    // f (N.L) is divided by N.L. The pdf is not part of a MaterialX shader: Result::pdf is NaN.
    std::vector<Result> evaluate(const Params& p, const std::vector<std::array<Vec3d, 2>>& pairs);

    // Sets the node's inputs (all but the vectors, which come from the geometry) to those of
    // `p`, in place of the values the document gave the shader, for the renders that follow:
    // one compiled program serves every document whose shader differs only in those values.
    void set_inputs(const Params& p);

    // A w x h image of the unit square z = 0 ([-1, 1]^2, normal +z) seen by a pinhole camera at
    // `eye` looking at the origin (vertical field of view fovDeg), lit by `lights`, with the
    // node's inputs as the document gives them (or as set_inputs last set them).
    MxImage render(int w, int h, const Vec3d& eye, double fovDeg,
                   const std::vector<MxLight>& lights);

    const std::string& fragment_source() const { return fragment_; }

  private:
    void set_material(const Params& p);
    static void bind_environment(unsigned program, unsigned envTex);
    EglContext context_;
    std::string node_;
    std::string vertex_, fragment_;
    unsigned program_ = 0;
    unsigned vao_ = 0, vbo_ = 0, fbo_ = 0, colorTex_ = 0, posProgram_ = 0;
    // A black 1 x 1 texture on unit 1 for the environment samplers, so that they never read
    // the render target (bound on unit 0) while it is drawn to.
    unsigned envTex_ = 0;
};

} // namespace retroprism::gl
