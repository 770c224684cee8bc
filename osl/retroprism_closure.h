// retroprism_closure.h: the prismatic retroreflector node as an Open Shading Language closure,
// for renderers built on OSL (tested with OSL 1.13). A renderer registers it once:
//
//   retroprism::osl::register_retroprism_closure(shadingSystem, MY_RETROPRISM_ID);
//
// and shaders call `retroprism_bsdf(...)`, declared in osl/shaders/retroprism.h (generated
// from the parameter table, like everything here). When walking a shader's closure tree, the
// renderer turns a component with that id into a RetroprismBsdf:
//
//   if (comp->id == MY_RETROPRISM_ID) {
//       retroprism::osl::RetroprismBsdf bsdf(*comp->as<retroprism::osl::ClosureParams>());
//       auto e = bsdf.eval(view, light);     // f without the cosine, pdf of light given view
//       auto s = bsdf.sample(view, u);       // a light direction, its f and pdf
//   }
//
// Conventions (OSL's: the closure is evaluated and sampled from the view side):
//  - view points from the shading point toward the viewer (-I), light toward the light; both
//    in the space the closure's normal and tangent are in (OSL's common space).
//  - f is the node's BRDF f(wi = light, wo = view) in 1/sr WITHOUT the cosine factor, the three
//    lobes summed, times the closure's own `weight` input (the component's weight is the
//    renderer's to apply).
//  - pdf is the density in 1/sr with which sample() draws `light` given `view`: the node's
//    one-sample-mixture pdf with the view as its incident direction (the node samples from wi;
//    its lobes are sampled about the view, and f is evaluated at the drawn light direction).
//  - sample() returns an empty optional where the node's does (view below the horizon,
//    nothing reflects, light drawn below the horizon).
#pragma once

#include <memory>
#include <optional>

#include <OSL/genclosure.h>
#include <OSL/oslclosure.h>
#include <OSL/oslexec.h>

#include "prismatic_retroreflector.h"

namespace retroprism::osl {

// The closure's name, as shaders call it.
constexpr const char* kClosureName = "retroprism_bsdf";

// The closure's parameters in the order of the parameter table (the order of the shader
// declaration's arguments): floats as float, colours as colours, enums as their int index,
// booleans as int (OSL has no bool), vectors as vectors (OSL's common space).
struct ClosureParams {
#define RP_FLOAT(name, def, lo, hi, doc) float name;
#define RP_COLOR(name, r, g, b, doc) OSL::Color3 name;
#define RP_ENUM(name, def, values, doc) int name;
#define RP_VECTOR(name, x, y, z, geomprop, doc) OSL::Vec3 name;
#define RP_BOOL(name, def, doc) int name;
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
};

// The ClosureParam table of ClosureParams (one entry per input, then the end marker).
const OSL::ClosureParam* closure_params();

// Registers the closure `retroprism_bsdf` under `id` (the renderer's choice of id).
void register_retroprism_closure(OSL::ShadingSystem& shadingSystem, int id);

// The node's inputs from the closure's, vectors included.
Params to_params(const ClosureParams& c);

// The node of a material (float precision, default frame): built once per distinct inputs,
// normal and tangent aside, and kept; the last kMaterialCacheEntries materials made are kept, so
// that a shading point costs a lookup (each thread keeps its last material: tens of ns when
// consecutive points share it), not a node (whose azimuth series take up to 50 ms to make).
// Thread-safe.
using Node = PrismaticRetroreflector<float>;
std::shared_ptr<const Node> material_node(const ClosureParams& c);
constexpr int kMaterialCacheEntries = 256;

// The closure at one shading point: its material's node and the shading frame of its normal
// and tangent (the node's frame, rp_make_frame, computed in double and rounded as the node
// rounds it), so that its values are those of a PrismaticRetroreflector<float> built with the
// same inputs.
class RetroprismBsdf {
  public:
    using vec3 = Node::vec3;
    struct Eval {
        OSL::Color3 f{0.0f};
        float pdf = 0.0f;
    };
    struct Sample {
        OSL::Vec3 light{0.0f};
        OSL::Color3 f{0.0f};
        float pdf = 0.0f;
        int lobe = -1; // RP_LOBE_SURFACE, RP_LOBE_RETRO or RP_LOBE_DIFFUSE
    };

    explicit RetroprismBsdf(const ClosureParams& c);

    Eval eval(const OSL::Vec3& view, const OSL::Vec3& light) const;
    // u in [0, 1)^3: u.z chooses the lobe, u.x and u.y sample it (the node's sample()).
    std::optional<Sample> sample(const OSL::Vec3& view, const OSL::Vec3& u) const;

    const Node& node() const { return *node_; }

  private:
    // f(wi = light, wo = view) in the local frame; zero where either is rejected.
    OSL::Color3 f_local(const vec3& light, const vec3& view) const;
    bool to_local(const OSL::Vec3& w, vec3& local) const;

    std::shared_ptr<const Node> node_;
    vec3 n_, t_, b_;
};

} // namespace retroprism::osl
