#include "retroprism_closure.h"

#include <cstring>
#include <deque>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <unordered_map>

namespace retroprism::osl {

const OSL::ClosureParam* closure_params() {
    using OSL::TypeColor;
    using OSL::TypeDesc;
    using OSL::TypeFloat;
    using OSL::TypeInt;
    using OSL::TypeVector;
    static const OSL::ClosureParam params[] = {
#define RP_FLOAT(name, def, lo, hi, doc) CLOSURE_FLOAT_PARAM(ClosureParams, name),
#define RP_COLOR(name, r, g, b, doc) CLOSURE_COLOR_PARAM(ClosureParams, name),
#define RP_ENUM(name, def, values, doc) CLOSURE_INT_PARAM(ClosureParams, name),
#define RP_VECTOR(name, x, y, z, geomprop, doc) CLOSURE_VECTOR_PARAM(ClosureParams, name),
#define RP_BOOL(name, def, doc) CLOSURE_INT_PARAM(ClosureParams, name),
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
        CLOSURE_FINISH_PARAM(ClosureParams)};
    return params;
}

void register_retroprism_closure(OSL::ShadingSystem& shadingSystem, int id) {
    shadingSystem.register_closure(kClosureName, id, closure_params(), nullptr, nullptr);
}

Params to_params(const ClosureParams& c) {
    Params p;
#define RP_FLOAT(name, def, lo, hi, doc) p.name = double(c.name);
#define RP_COLOR(name, r, g, b, doc)                                                               \
    p.name = {double(c.name.x), double(c.name.y), double(c.name.z)};
#define RP_ENUM(name, def, values, doc) p.name = c.name;
#define RP_VECTOR(name, dx, dy, dz, geomprop, doc)                                                 \
    p.name = {double(c.name.x), double(c.name.y), double(c.name.z)};
#define RP_BOOL(name, def, doc) p.name = c.name != 0;
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    return p;
}

namespace {

// The material of a closure: its sanitized inputs with the default frame (the frame is the
// shading point's).
Params material_params(const ClosureParams& c) {
    Params p = to_params(c);
    const Params defaults;
    p.normal = defaults.normal;
    p.tangent = defaults.tangent;
    return sanitize(p);
}

// The closure's inputs as they arrive, the vectors zeroed: compared as bytes (the struct's
// members are all 4-byte floats and ints: no padding). Inputs that sanitize to the same material
// (out of range, NaN, -0) may have different keys, and then nodes of their own.
ClosureParams material_key(const ClosureParams& c) {
    ClosureParams k = c;
#define RP_FLOAT(name, def, lo, hi, doc)
#define RP_COLOR(name, r, g, b, doc)
#define RP_ENUM(name, def, values, doc)
#define RP_VECTOR(name, dx, dy, dz, geomprop, doc) k.name = OSL::Vec3(0.0f);
#define RP_BOOL(name, def, doc)
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    return k;
}

std::string key_bytes(const ClosureParams& k) {
    return std::string(reinterpret_cast<const char*>(&k), sizeof k);
}

// The nodes made, by key: each thread first tries the material of its last lookup (consecutive
// shading points mostly share one), then the shared table under a reader's lock.
class MaterialCache {
  public:
    std::shared_ptr<const Node> get(const ClosureParams& c) {
        thread_local ClosureParams lastKey;
        thread_local std::shared_ptr<const Node> lastNode;
        const ClosureParams key = material_key(c);
        if (lastNode && std::memcmp(&key, &lastKey, sizeof key) == 0) return lastNode;
        lastNode = find_or_make(key_bytes(key), c);
        lastKey = key;
        return lastNode;
    }

  private:
    std::shared_ptr<const Node> find_or_make(const std::string& key, const ClosureParams& c) {
        {
            std::shared_lock<std::shared_mutex> lock(mutex_);
            auto it = nodes_.find(key);
            if (it != nodes_.end()) return it->second;
        }
        // Made outside the lock: another thread may make the same node meanwhile; the first
        // one kept wins.
        auto node = std::make_shared<const Node>(material_params(c));
        std::unique_lock<std::shared_mutex> lock(mutex_);
        auto [it, inserted] = nodes_.emplace(key, node);
        if (inserted) {
            order_.push_back(key);
            if (int(order_.size()) > kMaterialCacheEntries) {
                nodes_.erase(order_.front());
                order_.pop_front();
            }
        }
        return it->second;
    }

    std::shared_mutex mutex_;
    std::unordered_map<std::string, std::shared_ptr<const Node>> nodes_;
    std::deque<std::string> order_; // keys in the order made, oldest first
};

} // namespace

std::shared_ptr<const Node> material_node(const ClosureParams& c) {
    static MaterialCache cache;
    return cache.get(c);
}

RetroprismBsdf::RetroprismBsdf(const ClosureParams& c) : node_(material_node(c)) {
    // The frame as the node makes it from its inputs (sanitize: rp_make_frame in double), then
    // rounded to the float node's precision.
    f64::vec3 n, t, b;
    f64::rp_make_frame(f64::vec3(c.normal.x, c.normal.y, c.normal.z),
                       f64::vec3(c.tangent.x, c.tangent.y, c.tangent.z), n, t, b);
    n_ = vec3(n);
    t_ = vec3(t);
    b_ = glm::cross(n_, t_);
}

bool RetroprismBsdf::to_local(const OSL::Vec3& w, vec3& local) const {
    return core<float>::to_local(n_, t_, b_, vec3(w.x, w.y, w.z), local);
}

OSL::Color3 RetroprismBsdf::f_local(const vec3& light, const vec3& view) const {
    core<float>::lobes r;
    if (!core<float>::eval_f(node_->core_material(), light, view, r)) return OSL::Color3(0.0f);
    const vec3 f = r.surface + r.retro + r.diffuse;
    return OSL::Color3(f.x, f.y, f.z);
}

RetroprismBsdf::Eval RetroprismBsdf::eval(const OSL::Vec3& view, const OSL::Vec3& light) const {
    Eval out;
    vec3 v, l;
    if (!to_local(view, v) || !to_local(light, l)) return out;
    out.f = f_local(l, v);
    // The density of sample(view): the node's pdf with the view as its incident direction.
    core<float>::lobes r;
    float pdf = 0.0f;
    if (core<float>::eval(node_->core_material(), v, l, r, pdf)) out.pdf = pdf;
    return out;
}

std::optional<RetroprismBsdf::Sample> RetroprismBsdf::sample(const OSL::Vec3& view,
                                                             const OSL::Vec3& u) const {
    vec3 v;
    if (!to_local(view, v)) return std::nullopt;
    vec3 l;
    core<float>::lobes r;
    float pdf = 0.0f;
    int lobe = -1;
    if (!core<float>::sample(node_->core_material(), v, vec3(u.x, u.y, u.z), l, r, pdf, lobe))
        return std::nullopt;
    Sample s;
    const vec3 w = l.x * t_ + l.y * b_ + l.z * n_;
    s.light = OSL::Vec3(w.x, w.y, w.z);
    // f at the direction returned, as eval(view, s.light) gives it.
    vec3 lReturned;
    if (to_local(s.light, lReturned)) s.f = f_local(lReturned, v);
    s.pdf = pdf;
    s.lobe = lobe;
    return s;
}

} // namespace retroprism::osl
