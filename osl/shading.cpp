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
        if (errcode >= EH_WARNING) text += msg + (msg.empty() || msg.back() != '\n' ? "\n" : "");
    }
    std::string take() {
        std::string t;
        t.swap(text);
        return t;
    }

  private:
    std::string text;
};

Messages& messages() {
    static Messages m;
    return m;
}

struct NoParams {
    int unused;
};

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
    using OSL::TypeDesc;
    static const OSL::ClosureParam noParams[] = {CLOSURE_FINISH_PARAM(NoParams)};
    system_->register_closure("transparent", kTransparentClosureId, noParams, nullptr, nullptr);
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
