// fuzz_checks.h: the properties the fuzz targets check, shared by the libFuzzer targets
// (fuzz/fuzz_*.cpp) and by tests/backends/test_stress.cpp, which replays the checked-in corpus
// (fuzz/corpus/<target>/) and the crashes found through the same functions.
//
// Each check takes arbitrary bytes and throws rpfuzz::Violation when a property fails; the
// fuzz targets turn that into an abort (a crash for libFuzzer), the tests into a failure.
//  - closure: the bytes are the node's inputs bit for bit (every Params field, NaN, Inf and
//    denormals included; enums as any int), wi and wo (any bits), u (any value in [0, 1]) and
//    an albedo grid; PrismaticRetroreflector<float> or <double> must give finite non-negative
//    values, zero where the guards say so, pdf() equal to eval().pdf, a sample whose f and pdf
//    are eval and pdf at the sampled direction, and finite non-negative albedos;
//  - query: the bytes are a JSON document; parsing it either succeeds or throws one of
//    nlohmann's exceptions (parse_error, or out_of_range for a number beyond a double); parse_query
//    then either returns a query or throws an InputError naming the source; no other exception, no
//    crash. A query that parses is answered by the C++ node in double and in float, as the
//    cpp-double and cpp-float backends answer it (evaluate_node, io/answer.h; at most 64
//    samples), which must give finite non-negative values;
//  - mtlx: the bytes are a MaterialX document; parse_mtlx either returns documents whose
//    parameters are within the table's ranges or throws an InputError naming the file;
//    outline_mtlx_text (which sends graphs to MaterialX) either outlines it or throws an
//    InputError naming the file, and a document parse_mtlx reads is no graph and has the
//    same materials;
//  - alta: the bytes are an ALTA file; parse_alta either returns samples within the
//    documented ranges or throws an InputError naming the file;
//  - ra_table: the bytes are an R_A table (CSV); parse_ra_table either returns entries within
//    the documented ranges, each colour empty or one of ra_colors() (all empty or none), at
//    least one, no two with the same angles and colour, or throws an InputError naming the file
//    and a line.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <vector>

#include <nlohmann/json.hpp>

#include "alta_reader.h"
#include "answer.h"
#include "mtlx_reader.h"
#include "mtlx_writer.h"
#include "prismatic_retroreflector.h"
#include "query.h"
#include "ra_table.h"
#include "study_results.h"

namespace rpfuzz {

// A property that does not hold.
class Violation : public std::logic_error {
  public:
    using std::logic_error::logic_error;
};

// Reads values from the fuzzer's bytes; once they are used up, every value is zero.
class Bytes {
  public:
    Bytes(const std::uint8_t* data, size_t size) : data_(data), size_(size) {}
    template <class T>
    T take() {
        unsigned char buf[sizeof(T)] = {};
        const size_t n = std::min(sizeof(T), size_ - pos_);
        if (n > 0) std::memcpy(buf, data_ + pos_, n);
        pos_ += n;
        T v;
        std::memcpy(&v, buf, sizeof(T));
        return v;
    }
    // Any bits as a floating-point value of type Real (NaN, Inf and denormals included).
    template <class Real>
    Real real() {
        if constexpr (sizeof(Real) == 4) {
            return take<float>();
        } else {
            return take<double>();
        }
    }
    // A value in [0, 1] from any bits: a fraction of 2^32, with 0, 1 and the largest value
    // below 1 reachable exactly.
    template <class Real>
    Real unit() {
        const std::uint32_t b = take<std::uint32_t>();
        if (b == 0xFFFFFFFFu) return Real(1);
        if (b == 0xFFFFFFFEu) return std::nextafter(Real(1), Real(0));
        return Real(double(b) / 4294967296.0);
    }

  private:
    const std::uint8_t* data_;
    size_t size_;
    size_t pos_ = 0;
};

inline std::string hexfloat(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%a", v);
    return buf;
}

// The node's parameters, every field from raw bytes (enum indices as any int, booleans from
// one bit: other bytes would not be a bool).
inline retroprism::Params params_from_bytes(Bytes& in) {
    retroprism::Params p;
    retroprism::for_each_input(p, [&](const retroprism::ParamInfo&, auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>)
            v = in.take<double>();
        else if constexpr (std::is_same_v<T, retroprism::Color3>)
            for (double& c : v)
                c = in.take<double>();
        else if constexpr (std::is_same_v<T, int>)
            v = in.take<std::int32_t>();
        else
            v = (in.take<std::uint8_t>() & 1) != 0;
    });
    return p;
}

// The inverse of params_from_bytes: the bytes that make `p` (for seeds and regression tests).
inline std::vector<std::uint8_t> params_to_bytes(const retroprism::Params& p) {
    std::vector<std::uint8_t> out;
    auto put = [&](const auto& v) {
        const auto* b = reinterpret_cast<const std::uint8_t*>(&v);
        out.insert(out.end(), b, b + sizeof v);
    };
    retroprism::for_each_input(p, [&](const retroprism::ParamInfo&, const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>)
            put(v);
        else if constexpr (std::is_same_v<T, retroprism::Color3>)
            for (double c : v)
                put(c);
        else if constexpr (std::is_same_v<T, int>)
            put(std::int32_t(v));
        else
            put(std::uint8_t(v ? 1 : 0));
    });
    return out;
}

// A whole closure input: precision, parameters, wi, wo, u (each in [0, 1)) and albedo grid.
template <class Real>
std::vector<std::uint8_t> closure_input(const retroprism::Params& p, const glm::dvec3& wi,
                                        const glm::dvec3& wo, const glm::dvec3& u, int grid) {
    std::vector<std::uint8_t> out = {std::uint8_t(sizeof(Real) == 8 ? 1 : 0)};
    const std::vector<std::uint8_t> params = params_to_bytes(p);
    out.insert(out.end(), params.begin(), params.end());
    auto put = [&](const auto& v) {
        const auto* b = reinterpret_cast<const std::uint8_t*>(&v);
        out.insert(out.end(), b, b + sizeof v);
    };
    for (const glm::dvec3& w : {wi, wo})
        for (int c = 0; c < 3; ++c)
            put(Real(w[c]));
    for (int c = 0; c < 3; ++c)
        put(std::uint32_t(std::min(u[c], 0.99999999) * 4294967296.0));
    put(std::uint8_t(grid - 1));
    return out;
}

// All inputs, exactly, for messages.
inline std::string describe(const retroprism::Params& p) {
    std::ostringstream ss;
    retroprism::for_each_input(p, [&](const retroprism::ParamInfo& info, const auto& v) {
        using T = std::decay_t<decltype(v)>;
        ss << info.name << " ";
        if constexpr (std::is_same_v<T, double>)
            ss << hexfloat(v) << " ";
        else if constexpr (std::is_same_v<T, retroprism::Color3>)
            ss << hexfloat(v[0]) << "," << hexfloat(v[1]) << "," << hexfloat(v[2]) << " ";
        else
            ss << v << " ";
    });
    return ss.str();
}

template <class V>
std::string describe_vec(const V& v) {
    return "(" + hexfloat(double(v.x)) + ", " + hexfloat(double(v.y)) + ", " +
           hexfloat(double(v.z)) + ")";
}

inline bool ok_value(double v) {
    return std::isfinite(v) && v >= 0.0;
}

inline double rel_diff(double a, double b) {
    if (a == b) return 0.0;
    return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}

template <class Real>
constexpr double consistency_tolerance() {
    return sizeof(Real) == 4 ? 1e-5 : 1e-12; // relative, float / double
}

// The closure entry points of one precision on inputs from the bytes.
template <class Real>
void check_closure_real(Bytes& in) {
    using Node = retroprism::PrismaticRetroreflector<Real>;
    using vec3 = typename Node::vec3;
    using Core = retroprism::core<Real>;
    const retroprism::Params p = params_from_bytes(in);
    const vec3 wi(in.real<Real>(), in.real<Real>(), in.real<Real>());
    const vec3 wo(in.real<Real>(), in.real<Real>(), in.real<Real>());
    const vec3 u(in.unit<Real>(), in.unit<Real>(), in.unit<Real>());
    const int grid = 1 + int(in.take<std::uint8_t>() % 6);
    const Node node(p);
    const auto& m = node.core_material();
    const Real minCos = Real(retroprism::f64::RP_MIN_COS);
    const std::string where = std::string(sizeof(Real) == 4 ? "float" : "double") + " node {" +
                              describe(p) + "} wi " + describe_vec(wi) + " wo " + describe_vec(wo) +
                              " u " + describe_vec(u);
    auto fail = [&](const std::string& what) { throw Violation(what + " at " + where); };
    auto valid = [&](const vec3& w, vec3& local) {
        return node.to_local(w, local) && local.z >= minCos;
    };
    const bool weighted = m.weight > Real(0);
    vec3 wiL, woL;
    const bool wiValid = weighted && valid(wi, wiL);
    const bool pairValid = wiValid && valid(wo, woL);

    // The frame is orthonormal, and a direction comes into it unit (or as given, when it is
    // within RP_UNIT_TOL of unit): otherwise to_world does not invert to_local and the core
    // sees a direction of the wrong length.
    const double eps = double(std::numeric_limits<Real>::epsilon());
    const glm::dvec3 axes[3] = {glm::dvec3(node.to_world(vec3(Real(1), Real(0), Real(0)))),
                                glm::dvec3(node.to_world(vec3(Real(0), Real(1), Real(0)))),
                                glm::dvec3(node.to_world(vec3(Real(0), Real(0), Real(1))))};
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            if (!(std::abs(glm::dot(axes[i], axes[j]) - (i == j ? 1.0 : 0.0)) <= 8 * eps))
                fail("the frame is not orthonormal (axes " + std::to_string(i) + ", " +
                     std::to_string(j) + ")");
    for (const vec3& w : {wi, wo}) {
        vec3 local;
        if (!node.to_local(w, local)) continue;
        const glm::dvec3 wd(w);
        const double len2 = glm::dot(wd, wd);
        const double expected =
            std::abs(double(glm::dot(w, w)) - 1.0) <= 1e-6 ? std::sqrt(len2) : 1.0;
        const double length = glm::length(glm::dvec3(local));
        if (!(std::abs(length - expected) <= 16 * eps * expected))
            fail("to_local gave a direction of length " + hexfloat(length) + " for " +
                 describe_vec(w));
    }

    // eval and pdf.
    const typename Node::Eval e = node.eval(wi, wo);
    bool zero = e.pdf == Real(0);
    for (int c = 0; c < 3; ++c)
        for (Real v : {e.f.surface[c], e.f.retro[c], e.f.diffuse[c]}) {
            if (!ok_value(double(v))) fail("eval gave " + hexfloat(double(v)));
            zero = zero && v == Real(0);
        }
    if (!ok_value(double(e.pdf))) fail("eval gave pdf " + hexfloat(double(e.pdf)));
    if (!pairValid && !zero) fail("eval is not zero where the guards require it");
    const Real pdf = node.pdf(wi, wo);
    if (std::memcmp(&pdf, &e.pdf, sizeof pdf) != 0)
        fail("pdf() " + hexfloat(double(pdf)) + " differs from eval().pdf " +
             hexfloat(double(e.pdf)));

    // sample, and eval and pdf at the sampled direction.
    const auto s = node.sample(wi, u);
    if (s) {
        if (!wiValid) fail("a sample where the guards require none");
        for (int c = 0; c < 3; ++c) {
            for (Real v : {s->f.surface[c], s->f.retro[c], s->f.diffuse[c]})
                if (!ok_value(double(v))) fail("sample gave f " + hexfloat(double(v)));
            if (!std::isfinite(double(s->wo[c]))) fail("sample gave a non-finite direction");
        }
        if (!(std::isfinite(double(s->pdf)) && s->pdf > Real(0)))
            fail("sample gave pdf " + hexfloat(double(s->pdf)));
        // The core's sample at the same local wi, and its eval at the same local wo.
        vec3 coreWo;
        typename Core::lobes r, re;
        Real corePdf = 0, evalPdf = 0;
        int lobe = -1;
        if (!Core::sample(m, wiL, u, coreWo, r, corePdf, lobe) || lobe != s->lobe ||
            std::memcmp(&corePdf, &s->pdf, sizeof corePdf) != 0)
            fail("the node's sample differs from the core's");
        Core::eval(m, wiL, coreWo, re, evalPdf);
        const double tol = consistency_tolerance<Real>();
        double d = rel_diff(double(evalPdf), double(corePdf));
        for (int c = 0; c < 3; ++c) {
            d = std::max(d, rel_diff(double(re.surface[c]), double(r.surface[c])));
            d = std::max(d, rel_diff(double(re.retro[c]), double(r.retro[c])));
            d = std::max(d, rel_diff(double(re.diffuse[c]), double(r.diffuse[c])));
        }
        if (!(d <= tol)) fail("sample and eval at the sampled direction differ by " + hexfloat(d));
        // Through the node's frame, where the round trip reproduces the sampled local
        // direction (elsewhere a few ulps of rounding move it; the stress sweep measures that).
        vec3 back;
        if (node.to_local(s->wo, back) && std::memcmp(&back, &coreWo, sizeof back) == 0) {
            const typename Node::Eval e2 = node.eval(wi, s->wo);
            double d2 = rel_diff(double(e2.pdf), double(s->pdf));
            d2 = std::max(d2, rel_diff(double(node.pdf(wi, s->wo)), double(s->pdf)));
            for (int c = 0; c < 3; ++c) {
                d2 = std::max(d2, rel_diff(double(e2.f.surface[c]), double(s->f.surface[c])));
                d2 = std::max(d2, rel_diff(double(e2.f.retro[c]), double(s->f.retro[c])));
                d2 = std::max(d2, rel_diff(double(e2.f.diffuse[c]), double(s->f.diffuse[c])));
            }
            if (!(d2 <= tol))
                fail("sample and eval(wi, s.wo) differ by " + hexfloat(d2) + " (wo " +
                     describe_vec(s->wo) + ")");
        }
    }

    // albedo on a small grid.
    const typename Node::Albedo a = node.albedo(wi, grid);
    bool albedoZero = true;
    for (int c = 0; c < 3; ++c)
        for (Real v : {a.surface[c], a.retro[c], a.diffuse[c]}) {
            if (!ok_value(double(v))) fail("albedo gave " + hexfloat(double(v)));
            albedoZero = albedoZero && v == Real(0);
        }
    if (!wiValid && !albedoZero) fail("albedo is not zero where the guards require it");
}

// First byte: bit 0 chooses the precision; the rest are the inputs.
inline void check_closure(const std::uint8_t* data, size_t size) {
    Bytes in(data, size);
    if (in.take<std::uint8_t>() & 1)
        check_closure_real<double>(in);
    else
        check_closure_real<float>(in);
}

inline bool names(const std::string& message, const std::string& source) {
    return message.find(source) != std::string::npos;
}

// A C++ node's answer to a query (every lobe, their sum and the pdf) finite and non-negative.
inline void check_answer(const char* backend, const std::vector<retroprism::BackendResult>& answer,
                         const nlohmann::json& query) {
    auto text = [](const std::array<double, 3>& v) {
        return "(" + hexfloat(v[0]) + ", " + hexfloat(v[1]) + ", " + hexfloat(v[2]) + ")";
    };
    for (const retroprism::BackendResult& r : answer) {
        bool ok = ok_value(r.pdf);
        for (const std::array<double, 3>* rgb : {&r.f, &r.surface, &r.retro, &r.diffuse})
            for (double v : *rgb)
                ok = ok && ok_value(v);
        if (!ok)
            throw Violation(std::string(backend) + " answered f " + text(r.f) + ", surface " +
                            text(r.surface) + ", retro " + text(r.retro) + ", diffuse " +
                            text(r.diffuse) + ", pdf " + hexfloat(r.pdf) + " to the query " +
                            query.dump());
    }
}

inline void check_query(const std::uint8_t* data, size_t size) {
    const std::string source = "fuzz_query.json";
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(data, data + size);
    } catch (const nlohmann::json::exception&) {
        // Malformed JSON (parse_error) or a number beyond double's range (out_of_range 406):
        // the parser's own errors.
        return;
    }
    retroprism::Query q;
    try {
        q = retroprism::parse_query(j, source);
    } catch (const retroprism::InputError& e) {
        if (!names(e.what(), source))
            throw Violation(std::string("parse_query's error does not name the source: ") +
                            e.what());
        return;
    } catch (const std::exception& e) {
        throw Violation(std::string("parse_query threw ") + typeid(e).name() + ": " + e.what());
    }
    if (q.samples.size() > 64) q.samples.resize(64);
    check_answer("cpp-double", retroprism::evaluate_node<double>(q.material, q.samples), j);
    check_answer("cpp-float", retroprism::evaluate_node<float>(q.material, q.samples), j);
}

// Every value of a parameter set within its table range (the readers reject the others).
inline void check_in_range(const retroprism::Params& p, const std::string& what) {
    auto in = [&](double v, double lo, double hi, const char* name) {
        if (!(v >= lo && v <= hi))
            throw Violation(what + ": " + name + " = " + hexfloat(v) + " passed the reader");
    };
    retroprism::for_each_input(p, [&](const retroprism::ParamInfo& info, const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>) {
            in(v, info.min_value, info.max_value, info.name);
        } else if constexpr (std::is_same_v<T, retroprism::Color3>) {
            for (double c : v)
                if (info.type == retroprism::ParamType::Color)
                    in(c, 0.0, 1.0, info.name);
                else if (!std::isfinite(c))
                    throw Violation(what + ": " + info.name +
                                    " is not finite but passed the reader");
        } else if constexpr (std::is_same_v<T, int>) {
            in(double(v), 0.0, double(retroprism::enum_values(info).size()) - 1.0, info.name);
        }
    });
}

// outline_mtlx_text's contract (see the header); nothing when it threw.
inline std::optional<retroprism::MtlxOutline> check_outline(const std::string& text,
                                                            const std::string& name) {
    try {
        return retroprism::outline_mtlx_text(text, name);
    } catch (const retroprism::InputError& e) {
        if (!names(e.what(), name))
            throw Violation(std::string("outline_mtlx_text's error does not name the file: ") +
                            e.what());
    } catch (const std::exception& e) {
        throw Violation(std::string("outline_mtlx_text threw ") + typeid(e).name() + ": " +
                        e.what());
    }
    return std::nullopt;
}

inline void check_mtlx(const std::uint8_t* data, size_t size) {
    const std::string name = "fuzz_doc.mtlx";
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::optional<retroprism::MtlxOutline> outline = check_outline(text, name);
    retroprism::MtlxDocument doc;
    try {
        doc = retroprism::parse_mtlx(text, name);
    } catch (const retroprism::InputError& e) {
        if (!names(e.what(), name))
            throw Violation(std::string("parse_mtlx's error does not name the file: ") + e.what());
        return;
    } catch (const std::exception& e) {
        throw Violation(std::string("parse_mtlx threw ") + typeid(e).name() + ": " + e.what());
    }
    if (doc.materials.empty()) throw Violation("parse_mtlx returned a document without materials");
    if (!outline) throw Violation("outline_mtlx_text rejects a document parse_mtlx reads");
    if (outline->graph())
        throw Violation("outline_mtlx_text calls a graph a document parse_mtlx reads: " +
                        outline->graph_description());
    if (outline->materials.size() != doc.materials.size())
        throw Violation("outline_mtlx_text and parse_mtlx count different materials");
    for (size_t k = 0; k < doc.materials.size(); ++k)
        if (outline->materials[k] != doc.materials[k].name)
            throw Violation("outline_mtlx_text and parse_mtlx name material " + std::to_string(k) +
                            " differently");
    for (const retroprism::MtlxMaterial& m : doc.materials) {
        check_in_range(m.params, name + " material " + m.name);
        // The working-space conversion with a converter that scales: its errors name the file.
        try {
            const retroprism::Params w = retroprism::to_working_space(
                doc, m, [](const std::string&, const retroprism::Color3& c) {
                    return retroprism::Color3{c[0] * 1.25, c[1], c[2] * 0.5};
                });
            check_in_range(w, name + " material " + m.name + " in the working space");
        } catch (const retroprism::InputError& e) {
            if (!names(e.what(), name))
                throw Violation(std::string("to_working_space's error does not name the file: ") +
                                e.what());
        } catch (const Violation&) {
            throw;
        } catch (const std::exception& e) {
            throw Violation(std::string("to_working_space threw ") + typeid(e).name() + ": " +
                            e.what());
        }
    }
    // The writer's document of what was read reads back with the same enums and booleans, and
    // floats and colours to the writer's nine digits (1e-8 relative); it writes no vectors
    // (normal and tangent are the geometry's).
    for (const retroprism::MtlxMaterial& m : doc.materials) {
        retroprism::Params back;
        try {
            back = retroprism::parse_mtlx(retroprism::mtlx_document({{"round_trip", m.params}}, {}),
                                          "round_trip.mtlx")
                       .materials.at(0)
                       .params;
        } catch (const std::exception& e) {
            throw Violation(std::string("the writer's document of material ") + m.name +
                            " does not read back: " + e.what());
        }
        retroprism::for_each_input(m.params, [&](const retroprism::ParamInfo& info, const auto& v) {
            using T = std::decay_t<decltype(v)>;
            const T& w = *retroprism::input_field<T>(back, info.name);
            bool same = true;
            if constexpr (std::is_same_v<T, double>)
                same = std::abs(v - w) <= 1e-8 * std::max(1.0, std::abs(v));
            else if constexpr (std::is_same_v<T, retroprism::Color3>) {
                if (info.type == retroprism::ParamType::Vector) return;
                for (int k = 0; k < 3; ++k)
                    same = same && std::abs(v[k] - w[k]) <= 1e-8 * std::max(1.0, std::abs(v[k]));
            } else
                same = v == w;
            if (!same)
                throw Violation("material " + m.name + ": input " + info.name +
                                " changes in the writer's document");
        });
    }
    try {
        (void)retroprism::select_material(doc, "");
        (void)retroprism::select_material(doc, doc.materials.back().name);
    } catch (const std::exception& e) {
        throw Violation(std::string("select_material threw on a material it has: ") + e.what());
    }
}

inline void check_alta(const std::uint8_t* data, size_t size) {
    const std::string name = "fuzz_data.alta";
    const std::string text(reinterpret_cast<const char*>(data), size);
    retroprism::AltaData d;
    try {
        d = retroprism::parse_alta(text, name);
    } catch (const retroprism::InputError& e) {
        if (!names(e.what(), name))
            throw Violation(std::string("parse_alta's error does not name the file: ") + e.what());
        return;
    } catch (const std::exception& e) {
        throw Violation(std::string("parse_alta threw ") + typeid(e).name() + ": " + e.what());
    }
    if (d.samples.empty()) throw Violation("parse_alta returned no samples");
    const double halfPi = 1.5707963267948966;
    for (const retroprism::AltaSample& s : d.samples) {
        const std::string at = name + ":" + std::to_string(s.line);
        if (!(s.theta_l >= 0 && s.theta_l < halfPi) || !std::isfinite(s.x) || !std::isfinite(s.y) ||
            !(std::hypot(s.x, s.y) <= halfPi + 1e-9) || !(s.value >= 0 && std::isfinite(s.value)))
            throw Violation(at + ": a sample outside the documented ranges passed the reader");
        const glm::dvec3 wi = s.wi(), wo = s.wo();
        for (double v : {wi.x, wi.y, wi.z, wo.x, wo.y, wo.z, s.value_cos(d.cosine_factor),
                         s.value_cos(!d.cosine_factor)})
            if (!std::isfinite(v)) throw Violation(at + ": a non-finite direction or value");
        if (!(wi.z > 0) || !(wo.z >= -1e-9))
            throw Violation(at + ": a direction below the horizon");
    }
}

inline void check_ra_table(const std::uint8_t* data, size_t size) {
    const std::string name = "fuzz_table.csv";
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    retroprism::RaMeasurements t;
    try {
        t = retroprism::parse_ra_table(in, name);
    } catch (const retroprism::InputError& e) {
        if (std::string(e.what()).rfind(name + ":", 0) != 0)
            throw Violation(std::string("parse_ra_table's error does not start with FILE:LINE: ") +
                            e.what());
        return;
    } catch (const std::exception& e) {
        throw Violation(std::string("parse_ra_table threw ") + typeid(e).name() + ": " + e.what());
    }
    if (t.entries.empty()) throw Violation("parse_ra_table returned no entries");
    for (size_t i = 0; i < t.entries.size(); ++i) {
        const retroprism::RaEntry& e = t.entries[i];
        const std::string at = name + ":" + std::to_string(e.line);
        if (!(e.observation_deg > 0 && e.observation_deg <= 5) ||
            !(e.entrance_deg > -90 && e.entrance_deg < 90) || !(e.ra > 0 && std::isfinite(e.ra)) ||
            !(e.presentation_deg >= -180 && e.presentation_deg <= 180) ||
            (e.rotation_deg && !(*e.rotation_deg >= -360 && *e.rotation_deg <= 360)))
            throw Violation(at + ": an entry outside the documented ranges passed the reader");
        const std::vector<std::string>& colors = retroprism::ra_colors();
        if (e.color.empty() != t.entries[0].color.empty() ||
            (!e.color.empty() && std::find(colors.begin(), colors.end(), e.color) == colors.end()))
            throw Violation(at + ": colour \"" + e.color + "\" passed the reader");
        for (size_t k = 0; k < i; ++k) {
            const retroprism::RaEntry& p = t.entries[k];
            if (p.observation_deg == e.observation_deg && p.entrance_deg == e.entrance_deg &&
                p.rotation_deg == e.rotation_deg && p.presentation_deg == e.presentation_deg &&
                p.color == e.color)
                throw Violation(at + ": a duplicate of line " + std::to_string(p.line) +
                                " passed the reader");
        }
    }
}

// The accuracy study's files (sim/study_results.h): the archive of `simulate --study --load`,
// a shard's partial results (`--merge`) and results.csv. Each reader returns the whole grid (a
// shard: K/N in range, its units in order) or throws an InputError naming the file; nothing
// else (no crash, no other exception, no partial result).
inline void check_study(const std::uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    for (const bool quick : {true, false}) {
        const std::string name = "fuzz_study.txt";
        std::istringstream in(text);
        try {
            const retroprism::sim::StudyResults s = retroprism::sim::parse_study(in, name, quick);
            if (s.results.size() != s.grid.size())
                throw Violation("parse_study returned " + std::to_string(s.results.size()) +
                                " configurations for a grid of " + std::to_string(s.grid.size()));
        } catch (const retroprism::InputError& e) {
            if (!names(e.what(), name))
                throw Violation(std::string("parse_study's error does not name the file: ") +
                                e.what());
        }
    }
    const std::string shardName = "fuzz_shard.txt";
    std::istringstream shardIn(text);
    try {
        const retroprism::sim::StudyShard s =
            retroprism::sim::parse_study_shard(shardIn, shardName);
        const size_t units = retroprism::sim::study_units(s.options).size();
        if (!(s.shard.k >= 1 && s.shard.k <= s.shard.n && size_t(s.shard.n) <= units))
            throw Violation("parse_study_shard returned shard " + std::to_string(s.shard.k) + "/" +
                            std::to_string(s.shard.n) + " of a study of " + std::to_string(units) +
                            " units");
        for (size_t j = 0; j < s.units.size(); ++j)
            if (s.units[j].index >= units || (j > 0 && s.units[j].index <= s.units[j - 1].index))
                throw Violation("parse_study_shard returned units out of order or range");
    } catch (const retroprism::InputError& e) {
        if (!names(e.what(), shardName))
            throw Violation(std::string("parse_study_shard's error does not name the file: ") +
                            e.what());
    }
    const std::string csvName = "fuzz_results.csv";
    std::istringstream csv(text);
    try {
        retroprism::sim::parse_results_csv(csv, csvName);
    } catch (const retroprism::InputError& e) {
        if (!names(e.what(), csvName))
            throw Violation(std::string("parse_results_csv's error does not name the file: ") +
                            e.what());
    }
}

} // namespace rpfuzz
