#include "backend.h"

#include <cmath>
#include <functional>
#include <map>
#include <mutex>

#include "batch.h"
#include "gl_runner.h"
#include "mx_runner.h"
#include "paths.h"

namespace retroprism {

using nlohmann::json;

namespace {

// The C++ node in double (the reference) or float.
template <class Real>
class CppBackend final : public Backend {
  public:
    explicit CppBackend(std::string name) : name_(std::move(name)) {}
    std::string name() const override { return name_; }
    std::vector<BackendResult> evaluate(const Params& p,
                                        const std::vector<DirectionPair>& pairs) override {
        return evaluate_node<Real>(p, pairs);
    }

  private:
    std::string name_;
};

// The node over one batch of all the pairs (nodes/batch.h), in float, with the pdf.
class CppBatchBackend final : public Backend {
  public:
    std::string name() const override { return "cpp-batch"; }
    std::vector<BackendResult> evaluate(const Params& p,
                                        const std::vector<DirectionPair>& pairs) override {
        const std::size_t n = pairs.size();
        std::vector<float> in(6 * n), out(10 * n);
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                in[c * n + i] = float(pairs[i].wi[c]);
                in[(3 + c) * n + i] = float(pairs[i].wo[c]);
            }
        auto column = [&](int c) { return out.data() + c * n; };
        const BatchLobes lobes{{column(0), column(1), column(2)},
                               {column(3), column(4), column(5)},
                               {column(6), column(7), column(8)}};
        BatchEvaluator(p).eval(n, {&in[0], &in[n], &in[2 * n]},
                               {&in[3 * n], &in[4 * n], &in[5 * n]}, lobes, column(9));
        std::vector<BackendResult> res(n);
        for (std::size_t i = 0; i < n; ++i) {
            BackendResult& r = res[i];
            for (int c = 0; c < 3; ++c) {
                r.surface[c] = column(c)[i];
                r.retro[c] = column(3 + c)[i];
                r.diffuse[c] = column(6 + c)[i];
                // The sum in float, as the float node's Lobes::total().
                r.f[c] = double(column(c)[i] + column(3 + c)[i] + column(6 + c)[i]);
            }
            r.pdf = column(9)[i];
        }
        return res;
    }
};

std::vector<std::array<Vec3d, 2>> gl_pairs(const std::vector<DirectionPair>& pairs) {
    std::vector<std::array<Vec3d, 2>> out;
    out.reserve(pairs.size());
    for (const DirectionPair& s : pairs)
        out.push_back({s.wi, s.wo});
    return out;
}

std::vector<BackendResult> from_gl(const std::vector<gl::Result>& res) {
    auto d = [](const std::array<float, 3>& v) {
        return std::array<double, 3>{double(v[0]), double(v[1]), double(v[2])};
    };
    std::vector<BackendResult> out;
    out.reserve(res.size());
    for (const gl::Result& r : res) {
        const std::array<float, 3> f = {r.surface[0] + r.retro[0] + r.diffuse[0],
                                        r.surface[1] + r.retro[1] + r.diffuse[1],
                                        r.surface[2] + r.retro[2] + r.diffuse[2]};
        out.push_back({d(f), d(r.surface), d(r.retro), d(r.diffuse), double(r.pdf)});
    }
    return out;
}

// A backend on OpenGL: the generated full-runtime library (gl::Runner) or the shader real
// MaterialX generates (gl::MaterialXRunner, whose material is set through its uniforms). One
// context and program per process: compiling takes llvmpipe a while.
template <class Runner>
class GlBackend final : public Backend {
  public:
    GlBackend(std::string name, const std::string& source)
        : name_(std::move(name)), runner_(source) {}
    std::string name() const override { return name_; }
    std::vector<BackendResult> evaluate(const Params& p,
                                        const std::vector<DirectionPair>& pairs) override {
        return from_gl(runner_.evaluate(p, gl_pairs(pairs)));
    }

  private:
    std::string name_;
    Runner runner_;
};

// The portable nodegraph's GLSL: MaterialX's shader of the query document, generated with the
// library's genglsl implementation left out, so that MaterialX chooses the nodegraph.
class PortableRunner final : public gl::MaterialXRunner {
  public:
    explicit PortableRunner(const std::string& dataDir)
        : gl::MaterialXRunner(dataDir, "", "rp_query", "rp_query_bsdf", true) {}
};

using Factory = std::function<std::unique_ptr<Backend>()>;

const std::vector<std::pair<std::string, Factory>>& registry() {
    static const std::vector<std::pair<std::string, Factory>> r = {
        {"cpp-double", [] { return std::make_unique<CppBackend<double>>("cpp-double"); }},
        {"cpp-float", [] { return std::make_unique<CppBackend<float>>("cpp-float"); }},
        {"cpp-batch", [] { return std::make_unique<CppBatchBackend>(); }},
        {"glsl",
         [] { return std::make_unique<GlBackend<gl::Runner>>("glsl", gl::embedded_library()); }},
        {"materialx",
         [] { return std::make_unique<GlBackend<gl::MaterialXRunner>>("materialx", data_dir()); }},
    };
    return r;
}

const std::vector<std::pair<std::string, Factory>>& approximations() {
    static const std::vector<std::pair<std::string, Factory>> r = {
        {"materialx-portable",
         [] {
             return std::make_unique<GlBackend<PortableRunner>>("materialx-portable", data_dir());
         }},
    };
    return r;
}

json rgb_json(const std::array<double, 3>& v) {
    return json::array({v[0], v[1], v[2]});
}

std::vector<std::string> names_of(const std::vector<std::pair<std::string, Factory>>& table) {
    std::vector<std::string> n;
    for (const auto& [name, make] : table)
        n.push_back(name);
    return n;
}

} // namespace

const std::vector<std::string>& backend_names() {
    static const std::vector<std::string> names = names_of(registry());
    return names;
}

const std::vector<std::string>& approximation_names() {
    static const std::vector<std::string> names = names_of(approximations());
    return names;
}

Backend& backend(const std::string& name) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<Backend>> made;
    const std::lock_guard<std::mutex> lock(mutex);
    if (auto it = made.find(name); it != made.end()) return *it->second;
    for (const auto* table : {&registry(), &approximations()})
        for (const auto& [n, make] : *table)
            if (n == name) return *(made[name] = make());
    std::string names;
    for (const auto* list : {&backend_names(), &approximation_names()})
        for (const std::string& n : *list)
            names += (names.empty() ? "" : ", ") + n;
    throw InputError("--backend " + name + ": unknown backend (backends: " + names + ")");
}

json answer_query(const Query& q, const std::string& name) {
    json results = json::array();
    for (const BackendResult& r : backend(name).evaluate(q.material, q.samples)) {
        results.push_back({{"f", rgb_json(r.f)},
                           {"surface", rgb_json(r.surface)},
                           {"retro", rgb_json(r.retro)},
                           {"diffuse", rgb_json(r.diffuse)},
                           {"pdf", std::isnan(r.pdf) ? json(nullptr) : json(r.pdf)}});
    }
    return {{"backend", name}, {"results", results}};
}

} // namespace retroprism
