#include "approximation.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "check.h"
#include "color.h"
#include "error.h"
#include "paths.h"
#include "query.h"

namespace retroprism {

namespace fs = std::filesystem;

LobeErrors lobe_l1_errors(const std::string& name, const Params& p) {
    const std::vector<DirectionPair> pairs = standard_pairs(p);
    const std::vector<BackendResult> ref = backend("cpp-double").evaluate(p, pairs);
    const std::vector<BackendResult> got = backend(name).evaluate(p, pairs);
    // Per lobe (surface, retro, diffuse, f): sum |x - r| and sum |r|.
    double diff[4] = {0, 0, 0, 0}, mass[4] = {0, 0, 0, 0};
    for (size_t i = 0; i < pairs.size(); ++i) {
        const std::array<double, 3>* r[4] = {&ref[i].surface, &ref[i].retro, &ref[i].diffuse,
                                             &ref[i].f};
        const std::array<double, 3>* x[4] = {&got[i].surface, &got[i].retro, &got[i].diffuse,
                                             &got[i].f};
        for (int k = 0; k < 4; ++k)
            for (int c = 0; c < 3; ++c) {
                diff[k] += std::abs((*x[k])[size_t(c)] - (*r[k])[size_t(c)]);
                mass[k] += std::abs((*r[k])[size_t(c)]);
            }
    }
    auto rel = [&](int k) { return mass[k] > 0 ? diff[k] / mass[k] : 0.0; };
    return {rel(0), rel(1), rel(2), rel(3), long(pairs.size())};
}

std::vector<glm::dvec3> backend_f(const std::string& name, const Params& p,
                                  const std::vector<std::array<glm::dvec3, 2>>& dirs) {
    std::vector<DirectionPair> pairs;
    for (const auto& d : dirs)
        pairs.push_back({{d[0].x, d[0].y, d[0].z}, {d[1].x, d[1].y, d[1].z}});
    std::vector<glm::dvec3> f;
    for (const BackendResult& r : backend(name).evaluate(p, pairs))
        f.push_back({r.f[0], r.f[1], r.f[2]});
    return f;
}

std::vector<NamedMaterial> bundled_sheetings() {
    std::vector<std::pair<std::string, Params>> found;
    for (const char* folder : {"examples/materials", "examples/sheeting"}) {
        const fs::path dir = data_path(folder);
        if (!fs::is_directory(dir))
            throw InputError(dir.string() + ": no such folder (the bundled sheetings)");
        for (const auto& e : fs::directory_iterator(dir)) {
            const fs::path& f = e.path();
            if (f.extension() == ".json")
                found.push_back(
                    {f.stem().string(), params_from_json(read_json(f.string()), f.string())});
            else if (f.extension() == ".mtlx")
                found.push_back({f.stem().string(), document_params(f.string(), "")});
        }
    }
    std::sort(found.begin(), found.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<NamedMaterial> out;
    for (const auto& [name, params] : found) {
        for (int prism : {0, 1}) {
            Params p = params;
            p.prism_reflection = prism;
            out.push_back({name + (prism == 0 ? " ideal" : " tir"), p});
        }
        // Uncoated prisms lose retroreflection by azimuth: with the azimuth-averaged ERA too
        // (era_mode 0, the one the portable graph computes), when the sheeting has another.
        if (params.era_mode != 0) {
            Params p = params;
            p.prism_reflection = 1;
            p.era_mode = 0;
            out.push_back({name + " tir averaged", p});
        }
    }
    return out;
}

} // namespace retroprism
