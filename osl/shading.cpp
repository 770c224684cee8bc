#include "shading.h"

#include <stdexcept>

#include <OSL/genclosure.h>
#include <OSL/oslcomp.h>
#include <OSL/rendererservices.h>
#include <OpenImageIO/errorhandler.h>

#include "retroprism_closure.h"

namespace retroprism::osl {

namespace {

// Keeps the messages of a compiler or a shading system, for the exceptions thrown.
class Messages : public OIIO::ErrorHandler {
  public:
    void operator()(int errcode, const std::string& msg) override {
        if (errcode >= EH_WARNING) text_ += msg + (msg.empty() || msg.back() != '\n' ? "\n" : "");
    }
    std::string take() {
        std::string t;
        t.swap(text_);
        return t;
    }

  private:
    std::string text_;
};

Messages& messages() {
    static Messages m;
    return m;
}

struct NoParams {
    int unused;
};

// The parameters of stdosl.h's MaterialX closures (OSL 1.13) that the bundled documents call.
struct OrenNayarParams {
    OSL::Vec3 N;
    OSL::Color3 albedo;
    float roughness;
};
struct DielectricParams {
    OSL::Vec3 N, U;
    OSL::Color3 reflection_tint, transmission_tint;
    float roughness_x, roughness_y, ior;
    OSL::ustring distribution;
    float thinfilm_thickness, thinfilm_ior;
};
struct LayerParams {
    const OSL::ClosureColor* top;
    const OSL::ClosureColor* base;
};

void register_materialx_closures(OSL::ShadingSystem& system) {
    using OSL::TypeColor;
    using OSL::TypeDesc;
    using OSL::TypeFloat;
    using OSL::TypeString;
    using OSL::TypeVector;
    static const OSL::ClosureParam noParams[] = {CLOSURE_FINISH_PARAM(NoParams)};
    system.register_closure("transparent", kTransparentClosureId, noParams, nullptr, nullptr);
    static const OSL::ClosureParam orenNayar[] = {
        CLOSURE_VECTOR_PARAM(OrenNayarParams, N), CLOSURE_COLOR_PARAM(OrenNayarParams, albedo),
        CLOSURE_FLOAT_PARAM(OrenNayarParams, roughness), CLOSURE_FINISH_PARAM(OrenNayarParams)};
    system.register_closure("oren_nayar_diffuse_bsdf", kOrenNayarClosureId, orenNayar, nullptr,
                            nullptr);
    static const OSL::ClosureParam dielectric[] = {
        CLOSURE_VECTOR_PARAM(DielectricParams, N),
        CLOSURE_VECTOR_PARAM(DielectricParams, U),
        CLOSURE_COLOR_PARAM(DielectricParams, reflection_tint),
        CLOSURE_COLOR_PARAM(DielectricParams, transmission_tint),
        CLOSURE_FLOAT_PARAM(DielectricParams, roughness_x),
        CLOSURE_FLOAT_PARAM(DielectricParams, roughness_y),
        CLOSURE_FLOAT_PARAM(DielectricParams, ior),
        CLOSURE_STRING_PARAM(DielectricParams, distribution),
        CLOSURE_FLOAT_KEYPARAM(DielectricParams, thinfilm_thickness, "thinfilm_thickness"),
        CLOSURE_FLOAT_KEYPARAM(DielectricParams, thinfilm_ior, "thinfilm_ior"),
        CLOSURE_FINISH_PARAM(DielectricParams)};
    system.register_closure("dielectric_bsdf", kDielectricClosureId, dielectric, nullptr, nullptr);
    static const OSL::ClosureParam layer[] = {CLOSURE_CLOSURE_PARAM(LayerParams, top),
                                              CLOSURE_CLOSURE_PARAM(LayerParams, base),
                                              CLOSURE_FINISH_PARAM(LayerParams)};
    system.register_closure("layer", kLayerClosureId, layer, nullptr, nullptr);
}

} // namespace

// Every named space is common space, and every object's transformation the identity.
class ShaderRunner::Services : public OSL::RendererServices {
  public:
    bool get_matrix(OSL::ShaderGlobals*, OSL::Matrix44& result, OSL::TransformationPtr,
                    float) override {
        result.makeIdentity();
        return true;
    }
    bool get_matrix(OSL::ShaderGlobals*, OSL::Matrix44& result, OSL::TransformationPtr) override {
        result.makeIdentity();
        return true;
    }
    bool get_matrix(OSL::ShaderGlobals*, OSL::Matrix44& result, OSL::ustringhash, float) override {
        result.makeIdentity();
        return true;
    }
    bool get_matrix(OSL::ShaderGlobals*, OSL::Matrix44& result, OSL::ustringhash) override {
        result.makeIdentity();
        return true;
    }
};

ShaderRunner::ShaderRunner()
    : services_(std::make_unique<Services>()),
      system_(std::make_unique<OSL::ShadingSystem>(services_.get(), nullptr, &messages())) {
    register_retroprism_closure(*system_, kRetroprismClosureId);
    register_materialx_closures(*system_);
    thread_ = system_->create_thread_info();
    context_ = system_->get_context(thread_);
}

ShaderRunner::~ShaderRunner() {
    system_->release_context(context_);
    system_->destroy_thread_info(thread_);
}

void ShaderRunner::compile(const std::string& name, const std::string& source,
                           const std::vector<std::string>& includeDirs) {
    OSL::OSLCompiler compiler(&messages());
    std::vector<std::string> options;
    for (const std::string& dir : includeDirs)
        options.push_back("-I" + dir);
    std::string oso;
    messages().take();
    if (!compiler.compile_buffer(source, oso, options, "", name + ".osl"))
        throw std::runtime_error("oslc: " + name + ": " + messages().take());
    if (!system_->LoadMemoryCompiledShader(name, oso))
        throw std::runtime_error("liboslexec: " + name + ": " + messages().take());
}

void ShaderRunner::set_texture_searchpath(const std::string& folders) {
    system_->texturesys()->attribute("searchpath", folders);
}

ShaderRunner::Group ShaderRunner::group(const std::string& name,
                                        const std::vector<ParamValue>& params,
                                        const std::string& output) {
    messages().take();
    Group g{system_->ShaderGroupBegin(name), output};
    for (const ParamValue& p : params) {
        const void* value = p.type == OSL::TypeDesc::TypeInt
                                ? static_cast<const void*>(&p.integer)
                                : static_cast<const void*>(p.floats.data());
        if (!system_->Parameter(*g.ref, p.name, p.type, value))
            throw std::runtime_error("liboslexec: " + name + ": parameter " + p.name + ": " +
                                     messages().take());
    }
    if (!system_->Shader(*g.ref, "surface", name, "layer1") || !system_->ShaderGroupEnd(*g.ref))
        throw std::runtime_error("liboslexec: " + name + ": " + messages().take());
    if (output != "Ci") {
        const OSL::ustring out(output);
        system_->attribute(g.ref.get(), "renderer_outputs", OSL::TypeDesc(OSL::TypeDesc::STRING, 1),
                           &out);
    }
    return g;
}

namespace {

void flatten(const OSL::ClosureColor* c, const OSL::Color3& w, std::vector<Component>& out) {
    if (!c) return;
    if (c->id == OSL::ClosureColor::MUL) {
        const OSL::ClosureMul* m = c->as_mul();
        flatten(m->closure, w * m->weight, out);
    } else if (c->id == OSL::ClosureColor::ADD) {
        const OSL::ClosureAdd* a = c->as_add();
        flatten(a->closureA, w, out);
        flatten(a->closureB, w, out);
    } else {
        const OSL::ClosureComponent* comp = c->as_comp();
        out.push_back({comp->id, w * comp->w, comp->data()});
        if (comp->id == kLayerClosureId) {
            const LayerParams* layer = comp->as<LayerParams>();
            flatten(layer->top, w * comp->w, out);
            flatten(layer->base, w * comp->w, out);
        }
    }
}

} // namespace

std::vector<Component> ShaderRunner::shade(const Group& group, const ShadingPoint& point) {
    static const OSL::Matrix44 identity;
    OSL::ShaderGlobals sg{};
    sg.P = point.P;
    sg.N = sg.Ng = point.N;
    sg.I = point.I;
    sg.dPdu = point.dPdu;
    sg.dPdv = point.N.cross(point.dPdu);
    sg.u = point.u;
    sg.v = point.v;
    sg.renderer = system_->renderer();
    sg.object2common = sg.shader2common = &identity;
    sg.surfacearea = 1.0f;
    sg.raytype = 1; // camera
    messages().take();
    if (!system_->execute(*context_, *group.ref, 0, 0, sg, nullptr, nullptr))
        throw std::runtime_error("liboslexec: execute: " + messages().take());
    const OSL::ClosureColor* root = sg.Ci;
    if (group.output != "Ci") {
        OSL::TypeDesc type;
        const void* at = system_->get_symbol(*context_, OSL::ustring(group.output), type);
        if (!at) throw std::runtime_error("liboslexec: no output " + group.output);
        root = *static_cast<const OSL::ClosureColor* const*>(at);
    }
    std::vector<Component> out;
    flatten(root, OSL::Color3(1.0f), out);
    return out;
}

} // namespace retroprism::osl
