// shading.h: shaders run through liboslexec as a renderer runs them, on a minimal renderer: a
// shading system with the retroprism_bsdf closure registered, and the closures of OSL's stdosl.h
// that MaterialX's OSL of the bundled documents calls (transparent, which its surfacematerial
// emits; oren_nayar_diffuse_bsdf, dielectric_bsdf, layer); shaders compiled in process by
// liboslcomp (what oslc runs), executed one shading point at a time, their closure trees
// flattened into weighted components. Only retroprism_bsdf is evaluated (RetroprismBsdf): the
// others are read as components, a layer as its two closures, its base's weight not attenuated
// by the top (OSL leaves layering to the renderer). Every space (common, world, object, shader)
// is the same: the scene's objects are untransformed. One thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <OSL/oslclosure.h>
#include <OSL/oslexec.h>

namespace retroprism::osl {

// The closure ids this renderer registers.
constexpr int kRetroprismClosureId = 1;
constexpr int kTransparentClosureId = 2;
constexpr int kOrenNayarClosureId = 3;
constexpr int kDielectricClosureId = 4;
constexpr int kLayerClosureId = 5;

// A leaf of a closure tree with the product of the weights above it. `params` points into the
// shading context's closure memory: valid until the next shade().
struct Component {
    int id = -1;
    OSL::Color3 weight{0.0f};
    const void* params = nullptr;
};

// A shader parameter's value for a group (Parameter() before Shader()).
struct ParamValue {
    std::string name;
    OSL::TypeDesc type;
    std::vector<float> floats; // float, color, vector
    int integer = 0;           // int
};

// A shading point: position, shading normal, the incoming ray's direction (I, toward the
// surface), the surface's tangent dPdu and its texture coordinates.
struct ShadingPoint {
    OSL::Vec3 P{0.0f}, N{0.0f, 0.0f, 1.0f}, I{0.0f, 0.0f, -1.0f}, dPdu{1.0f, 0.0f, 0.0f};
    float u = 0.0f, v = 0.0f;
};

class ShaderRunner {
  public:
    ShaderRunner();
    ~ShaderRunner();
    ShaderRunner(const ShaderRunner&) = delete;
    ShaderRunner& operator=(const ShaderRunner&) = delete;

    // Compiles OSL source with liboslcomp (#include searched in `includeDirs`, then OSL's
    // stdosl.h) and loads it as the shader `name`; throws std::runtime_error with the
    // compiler's messages on failure.
    void compile(const std::string& name, const std::string& source,
                 const std::vector<std::string>& includeDirs);

    // A group of the one surface shader `name` with `params` set; the closure is read from
    // `output` ("Ci", or an output parameter of the shader, such as MaterialX's "out").
    // Throws when the shading system rejects a parameter or the shader.
    struct Group {
        OSL::ShaderGroupRef ref;
        std::string output;
    };
    Group group(const std::string& name, const std::vector<ParamValue>& params,
                const std::string& output = "Ci");

    // Executes the group at one point; the leaves of its closure (empty when the shader made
    // none). Throws when execution fails.
    std::vector<Component> shade(const Group& group, const ShadingPoint& point);

    // Where the texture system looks for relative file names (OpenImageIO's "searchpath").
    void set_texture_searchpath(const std::string& folders);

    OSL::ShadingSystem& shading_system() { return *system_; }

  private:
    class Services;
    std::unique_ptr<Services> services_;
    std::unique_ptr<OSL::ShadingSystem> system_;
    OSL::PerThreadInfo* thread_ = nullptr;
    OSL::ShadingContext* context_ = nullptr;
};

} // namespace retroprism::osl
