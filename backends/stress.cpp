// stress.cpp: the adversarial sweep of every backend (`retroprism check --stress`, issue 8).
//
// A deterministic generator concentrates on the places where a BRDF implementation breaks:
//  - materials: every combination of the enums and booleans of the parameter table, then each
//    parameter alone at its hard values (its range ends and their double and float neighbours,
//    every clamp and switch of the core: roughness 0, 1e-6, RP_MIN_ALPHA = 1e-4 and its
//    neighbours, 1, > 1; ior 1 - eps, 1, 1 + eps, 1.0001, 1.01 (the F_dr quadrature switch) and
//    its neighbours, 3, > 3; colours 0, 1, negative, > 1; enum indices out of range; -0, double
//    and float denormals, huge values, +-Inf and NaN), tilted, opposite, zero, non-finite,
//    overflowing and parallel normals and tangents; then random combinations of hard values;
//  - direction pairs, per material, in the input precision of the backend (float for
//    cpp-float, glsl and materialx, whose inputs are floats): incident directions from normal
//    to grazing (cosines 1e-7, RP_MIN_COS = 1e-9 and its neighbours, 0, -0, denormals,
//    negative), non-unit, zero, overflowing and non-finite ones; for each, outgoing ones at
//    wo = wi exactly and one ulp away in each component, the mirror direction and its ulp
//    neighbours, the lobes' own scale around both, grazing and below the horizon, the
//    opposite direction, non-finite, zero and random ones. Directions are made in the local
//    frame and taken into the parameter frame of the node (tilted frames), then rounded to the
//    backend's precision; ulp neighbours are taken after that rounding.
// Every value a backend returns is checked: NaN, Inf and negative values are counted (the
// required count is zero), and the guards of the contract must hold (a zero or non-finite
// direction, and in C++ one below RP_MIN_COS or a zero weight, gives exactly zero and an empty
// sample). The C++ backends are also sampled (u at 0, 1 and one ulp below, at the
// lobe-selection boundaries, random) and asked for albedos (8 x 8 grid); a sample's f and pdf
// must equal eval and pdf at the sampled direction, relative 1e-12 in double and 1e-5 in float,
// (1) at the same local direction (the core's sample and eval), and (2) through the node,
// eval(wi, s.wo) and pdf(wi, s.wo). In a tilted frame (2) differs from (1) by the rounding of
// the frame's round trip (to_world in sample, to_local in eval); where the frame is orthonormal
// to 8 ulp and the round trip moved the direction by at most 16 ulp, such a difference is
// counted apart ("round-trip") and is not a failure; anything else is an inconsistency.
// sample() is also called with u outside its contract [0, 1)^3 (NaN, Inf, negative, > 1): it
// clamps u (NaN taken as 0), so such a sample must be finite and non-negative too.
//
// Sizes: 1e7 evaluations for each C++ backend and 1e6 for each GL one, batched per material
// (one query of about 2500 pairs each). Measured here (two cores, llvmpipe): cpp-double 5 s,
// cpp-float 4 s, glsl 2 s, materialx 35 s on an idle machine, up to four times that under load.
// tests/test_stress.cpp compiles this file and runs a bounded version (Options::pair_stride).
#include "stress.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "backend.h"
#include "query.h"

namespace retroprism {
namespace stress {

using nlohmann::json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDblMax = std::numeric_limits<double>::max();
constexpr double kDblDenorm = std::numeric_limits<double>::denorm_min();
constexpr double kDblEps = std::numeric_limits<double>::epsilon();
constexpr double kFltEps = double(std::numeric_limits<float>::epsilon());
const double kMinAlpha = f64::RP_MIN_ALPHA;
const double kMinCos = f64::RP_MIN_COS;

// Sizes of the full sweep (issue 8): evaluations per backend.
constexpr long kCppEvaluations = 10000000;
constexpr long kGlEvaluations = 1000000;

// A fixed-seed generator (splitmix64): the same stream on every platform.
class Rng {
  public:
    explicit Rng(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * 0x1.0p-53; } // [0, 1)
    size_t index(size_t n) { return size_t(next() % n); }

  private:
    std::uint64_t state_;
};

// Neighbours in double and in float (returned as double).
double next_d(double x, double toward) {
    return std::nextafter(x, toward);
}
double next_f(double x, double toward) {
    return double(std::nextafter(float(x), float(toward)));
}

// ---- Materials --------------------------------------------------------------------------

// The hard values of a float input with range [lo, hi] and default def: the range ends, their
// neighbours in double and float, the default, the centre, signed zero, denormals (double's
// smallest, and 1e-40, a float denormal), values outside the range, the largest doubles,
// infinities and NaN (both signs).
std::vector<double> float_hard_values(double lo, double hi, double def) {
    return {lo,
            hi,
            def,
            0.5 * (lo + hi),
            next_d(lo, -kInf),
            next_d(lo, kInf),
            next_f(lo, -kInf),
            next_f(lo, kInf),
            next_d(hi, -kInf),
            next_d(hi, kInf),
            next_f(hi, -kInf),
            next_f(hi, kInf),
            -0.0,
            kDblDenorm,
            1e-40,
            -1e-40,
            1e-30,
            -1.0,
            hi + 1.0,
            2.0 * hi + 10.0,
            1e30,
            -1e30,
            1e300,
            kDblMax,
            -kDblMax,
            kInf,
            -kInf,
            kNaN,
            -kNaN};
}

// The switch points of the core for particular inputs (prism_core.inc and
// prismatic_retroreflector.cpp).
std::vector<double> named_hard_values(const std::string& name) {
    if (name == "roughness") {
        // RP_MIN_ALPHA = 1e-4 floors alpha; 1e-4 is not a float: both roundings matter.
        return {1e-6,
                1e-5,
                kMinAlpha,
                next_d(kMinAlpha, 0.0),
                next_d(kMinAlpha, 1.0),
                double(float(kMinAlpha)),
                next_f(kMinAlpha, 0.0),
                next_f(kMinAlpha, 1.0),
                kMinAlpha * (1.0 - 1e-7),
                kMinAlpha * (1.0 + 1e-7),
                2e-4,
                1e-3,
                0.005,
                0.05,
                0.3,
                0.9999999,
                1.0000001,
                2.0,
                10.0};
    }
    if (name == "ior") {
        // eta = 1 (no interface), 1 + eps (the cancellations the core avoids), 1.01 (the
        // F_dr quadrature switch in fdr_external), 3 (the top of the range).
        return {1.0 - 1e-7,
                1.0 + kDblEps,
                1.0 + 2.0 * kDblEps,
                1.0 + kFltEps,
                1.0 + 1e-7,
                1.0 + 1e-6,
                1.0 + 1.0 / 8192.0,
                1.0001,
                1.01,
                next_d(1.01, 0.0),
                next_d(1.01, 2.0),
                next_f(1.01, 0.0),
                next_f(1.01, 2.0),
                1.25,
                1.49,
                1.586,
                2.0,
                2.9999999,
                3.0000001,
                3.5,
                5.0,
                0.5,
                0.0};
    }
    if (name == "orientation") {
        return {30.0,   60.0, 90.0,  120.0, 180.0, 240.0, 300.0, 359.9, 359.99999,       720.0,
                -720.0, 1e10, -1e10, 1e-7,  -1e-7, 0.5,   45.0,  1e20,  next_d(360, 0.0)};
    }
    // weight, specular, metal_reflectance: tiny and nearly-one weights.
    return {1e-300, 1e-38, 1e-20, 1e-7, 0.25, 1.0 - 1e-7, 1.0 - kDblEps};
}

// The hard values of one colour input (per channel triples).
std::vector<Color3> color_hard_values() {
    return {{0, 0, 0},
            {1, 1, 1},
            {0, 1, 0.5},
            {1, 0, 0},
            {0, 0, 1},
            {-0.5, 0.5, 1.5},
            {-1, -1, -1},
            {2, 2, 2},
            {kNaN, 0.5, 1},
            {kNaN, kNaN, kNaN},
            {kInf, -kInf, 0.5},
            {kInf, kInf, kInf},
            {1e-40, kDblDenorm, 1},
            {1.0 - kDblEps, kDblEps, 0.5},
            {next_f(1.0, 0.0), next_f(0.0, 1.0), 1e-7},
            {-0.0, -0.0, -0.0},
            {1e30, -1e30, kDblMax},
            {1e-30, 1e-20, 1e-10}};
}

std::vector<int> enum_hard_values(int count) {
    return {-1,
            count,
            count + 1,
            -1000,
            1000,
            std::numeric_limits<int>::min(),
            std::numeric_limits<int>::max()};
}

std::vector<Vec3d> normal_hard_values() {
    return {{0, 0, 1},
            {0, 0, -1},
            {0.2, -0.1, 1.0},
            {1, 1, 1},
            {0.999, 0, 0.04},
            {1, 0, 0}, // along the default tangent: the tangent is replaced
            {0, 0, 0}, // zero: +z
            {-0.0, -0.0, -0.0},
            {kNaN, 0, 1}, // non-finite: +z
            {0, kInf, 1},
            {kInf, kInf, kInf},
            {-kInf, 0, 0},
            {1e-200, 0, 1e-200}, // tiny: squared length underflows in double
            {1e-40, 1e-40, 1e-40},
            {1e-20, 0, 1e-20},     // squared length underflows in float
            {1e200, 1e200, 1e200}, // squared length overflows
            {1e19, 0, 1e19},       // beyond a float's squared range
            {0, 0, 1e-300},
            {kDblDenorm, 0, 0},
            {1e-9, 0, -1}, // Duff et al.'s basis at the singular side
            {0, -1e-300, -1},
            {0, 0, 1.0 + 1e-7},
            {0.3, 0.4, 2.0}};
}

// Tangents: parallel to the default normal (either way), zero, non-finite, nearly parallel
// (squared orthogonal part 1e-14, below the 1e-12 threshold; at it; above it), opposite,
// oblique, huge, tiny, float-denormal, and along the bitangent.
std::vector<Vec3d> tangent_hard_values() {
    return {{1, 0, 0},           {0, 0, 1},     {0, 0, -1},      {0, 0, 0},
            {kNaN, kNaN, kNaN},  {kInf, 0, 0},  {1e-7, 0, 1},    {1e-6, 0, 1},
            {2e-6, 0, 1},        {-1, 0, 0},    {0.3, 0.9, 0.1}, {1e200, 1e200, 0},
            {1e-200, 1e-200, 0}, {1e-40, 0, 0}, {0, 1, 0}};
}

// One change of a material: a label and what it does.
struct Mutation {
    std::string label;
    std::function<void(Params&)> apply;
};

std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

// Every input alone at each of its hard values.
std::vector<Mutation> single_mutations() {
    std::vector<Mutation> out;
    for (const ParamInfo& info : param_table()) {
        const std::string name = info.name;
        switch (info.type) {
        case ParamType::Float: {
            std::vector<double> values =
                float_hard_values(info.min_value, info.max_value, info.default_value[0]);
            for (double v : named_hard_values(name))
                values.push_back(v);
            for (double v : values)
                out.push_back({name + "=" + num(v),
                               [name, v](Params& p) { *input_field<double>(p, name) = v; }});
            break;
        }
        case ParamType::Color:
            for (const Color3& c : color_hard_values())
                out.push_back({name + "=(" + num(c[0]) + "," + num(c[1]) + "," + num(c[2]) + ")",
                               [name, c](Params& p) { *input_field<Color3>(p, name) = c; }});
            break;
        case ParamType::Enum:
            for (int v : enum_hard_values(int(enum_values(info).size())))
                out.push_back({name + "=" + std::to_string(v),
                               [name, v](Params& p) { *input_field<int>(p, name) = v; }});
            break;
        case ParamType::Bool:
            break; // both values are in every base combination
        case ParamType::Vector: {
            const std::vector<Vec3d> values =
                name == "normal" ? normal_hard_values() : tangent_hard_values();
            for (const Vec3d& v : values)
                out.push_back({name + "=(" + num(v[0]) + "," + num(v[1]) + "," + num(v[2]) + ")",
                               [name, v](Params& p) { *input_field<Vec3d>(p, name) = v; }});
            break;
        }
        }
    }
    // Frames whose tangent is parallel, or nearly, to a tilted normal.
    const Vec3d tilted = {0.2, -0.1, 1.0};
    for (double eps : {0.0, 1e-9, 1e-6, 1e-3}) {
        out.push_back({"normal=tilted,tangent=normal+" + num(eps), [tilted, eps](Params& p) {
                           p.normal = tilted;
                           p.tangent = {tilted[0] + eps, tilted[1], tilted[2]};
                       }});
    }
    return out;
}

// The enum and boolean inputs and their number of values.
std::vector<std::pair<std::string, int>> discrete_inputs() {
    std::vector<std::pair<std::string, int>> out;
    for (const ParamInfo& info : param_table()) {
        if (info.type == ParamType::Enum)
            out.push_back({info.name, int(enum_values(info).size())});
        else if (info.type == ParamType::Bool)
            out.push_back({info.name, 2});
    }
    return out;
}

long combination_count() {
    long n = 1;
    for (const auto& d : discrete_inputs())
        n *= d.second;
    return n;
}

// Combination k of the enum and boolean values, on the default material.
Params combination(long k) {
    Params p;
    for (const auto& d : discrete_inputs()) {
        const int v = int(k % d.second);
        k /= d.second;
        if (int* e = input_field<int>(p, d.first))
            *e = v;
        else if (bool* b = input_field<bool>(p, d.first))
            *b = v != 0;
    }
    return p;
}

// Material number `index` of the sweep and a label for it. The sequence: every combination of
// the enums and booleans; each single mutation, on the combinations in turn; then random
// materials whose inputs are each a hard value (probability 0.4) or a random in-range value.
Params material(long index, std::string* label) {
    static const std::vector<Mutation> singles = single_mutations();
    const long combos = combination_count();
    if (index < combos) {
        if (label) *label = "combination " + std::to_string(index);
        return combination(index);
    }
    index -= combos;
    if (index < long(singles.size())) {
        Params p = combination((index * 7) % combos);
        singles[size_t(index)].apply(p);
        if (label)
            *label = "combination " + std::to_string((index * 7) % combos) + " with " +
                     singles[size_t(index)].label;
        return p;
    }
    index -= long(singles.size());
    Rng rng(0x5eed0000ull + std::uint64_t(index));
    Params p = combination(long(rng.index(size_t(combos))));
    std::string what;
    for (const ParamInfo& info : param_table()) {
        const std::string name = info.name;
        const bool hard = rng.uniform() < 0.4;
        switch (info.type) {
        case ParamType::Float: {
            double* f = input_field<double>(p, name);
            if (hard) {
                std::vector<double> values =
                    float_hard_values(info.min_value, info.max_value, info.default_value[0]);
                for (double v : named_hard_values(name))
                    values.push_back(v);
                *f = values[rng.index(values.size())];
            } else {
                *f = info.min_value + (info.max_value - info.min_value) * rng.uniform();
            }
            break;
        }
        case ParamType::Color: {
            Color3* c = input_field<Color3>(p, name);
            if (hard) {
                const std::vector<Color3> values = color_hard_values();
                *c = values[rng.index(values.size())];
            } else {
                *c = {rng.uniform(), rng.uniform(), rng.uniform()};
            }
            break;
        }
        case ParamType::Enum:
            if (hard) {
                const std::vector<int> values = enum_hard_values(int(enum_values(info).size()));
                *input_field<int>(p, name) = values[rng.index(values.size())];
            }
            break;
        case ParamType::Bool:
            break;
        case ParamType::Vector: {
            Vec3d* v = input_field<Vec3d>(p, name);
            if (hard) {
                const std::vector<Vec3d> values =
                    name == "normal" ? normal_hard_values() : tangent_hard_values();
                *v = values[rng.index(values.size())];
            } else if (rng.uniform() < 0.5) {
                *v = {2 * rng.uniform() - 1, 2 * rng.uniform() - 1,
                      name == "normal" ? 0.2 + rng.uniform() : 2 * rng.uniform() - 1};
            }
            break;
        }
        }
    }
    if (label) *label = "random material " + std::to_string(index);
    return p;
}

// All inputs of a material, exactly (for reports).
std::string describe(const Params& p) {
    std::string s = "{";
    auto add = [&](const std::string& k, const std::string& v) {
        s += (s.size() > 1 ? ", " : "") + k + ": " + v;
    };
    auto v3 = [](const std::array<double, 3>& v) {
        return "[" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + "]";
    };
#define RP_FLOAT(n, def, lo, hi, doc) add(#n, num(p.n));
#define RP_COLOR(n, r, g, b, doc) add(#n, v3(p.n));
#define RP_ENUM(n, def, values, doc) add(#n, std::to_string(p.n));
#define RP_VECTOR(n, x, y, z, geomprop, doc) add(#n, v3(p.n));
#define RP_BOOL(n, def, doc) add(#n, p.n ? "true" : "false");
#include "prismatic_retroreflector_params.def"
#undef RP_FLOAT
#undef RP_COLOR
#undef RP_ENUM
#undef RP_VECTOR
#undef RP_BOOL
    return s + "}";
}

std::string describe(const Vec3d& v) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g) [%a, %a, %a]", v[0], v[1], v[2], v[0],
                  v[1], v[2]);
    return buf;
}

// ---- Direction pairs --------------------------------------------------------------------

// Builds the pairs of one material in the backend's input precision.
class PairBuilder {
  public:
    PairBuilder(const Params& p, bool floatInputs) : node_(p), float_(floatInputs) {}

    double round(double x) const { return float_ ? double(float(x)) : x; }
    Vec3d round(const glm::dvec3& v) const { return {round(v.x), round(v.y), round(v.z)}; }
    double next(double x, double toward) const {
        return float_ ? next_f(x, toward) : next_d(x, toward);
    }
    // A local-frame direction in the parameter frame, rounded.
    Vec3d parent(const glm::dvec3& local) const { return round(node_.to_world(local)); }

    const PrismaticRetroreflector<double>& node() const { return node_; }

  private:
    PrismaticRetroreflector<double> node_;
    bool float_;
};

glm::dvec3 from_cos(double c, double phiDeg) {
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double p = phiDeg * M_PI / 180.0;
    return {s * std::cos(p), s * std::sin(p), c};
}

glm::dvec3 from_deg(double thetaDeg, double phiDeg) {
    return from_cos(std::cos(thetaDeg * M_PI / 180.0), phiDeg);
}

// A unit direction in the xy-plane at azimuth phi with the given z (not normalised: z is the
// tiny cosine itself).
glm::dvec3 grazing(double z, double phiDeg) {
    const double p = phiDeg * M_PI / 180.0;
    return {std::cos(p), std::sin(p), z};
}

// Incident directions in the local frame: normal, nearly normal, oblique, grazing (cosines at
// and around RP_MIN_COS, zero, signed zero, denormals, slightly negative) and below the horizon.
std::vector<glm::dvec3> incident_set(Rng& rng, double alpha) {
    std::vector<glm::dvec3> out;
    out.push_back({0, 0, 1});
    for (double theta : {0.5, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.5, 89.99})
        out.push_back(from_deg(theta, 360.0 * rng.uniform()));
    out.push_back(from_deg(60.0, 0.0));
    out.push_back(from_deg(60.0, 90.0));
    // Nearly normal: tan(theta_i) at and around RP_VNDF_MIN_TAN = 1e-7, where the surface
    // lobe's visible-normal sampling switches to the plain Gaussian; the switch applies to the
    // direction stretched by alpha, so also at 1e-7 / alpha.
    for (double t : {5e-8, 1e-7, 2e-7, 0.5e-7 / alpha, 1e-7 / alpha, 2e-7 / alpha}) {
        const double phi = 2.0 * M_PI * rng.uniform();
        out.push_back(glm::normalize(glm::dvec3(t * std::cos(phi), t * std::sin(phi), 1.0)));
    }
    for (double z :
         {1e-7, kMinCos, next_d(kMinCos, 0.0), next_d(kMinCos, 1.0), double(float(kMinCos)),
          next_f(kMinCos, 0.0), next_f(kMinCos, 1.0), 1e-40, kDblDenorm, 0.0, -0.0, -1e-40, -1e-7})
        out.push_back(grazing(z, 360.0 * rng.uniform()));
    out.push_back(from_deg(100.0, 30.0));
    out.push_back({0, 0, -1});
    out.push_back(from_deg(120.0, 200.0));
    return out;
}

// Zero, non-finite and scaled versions of a direction (in the parameter frame): scaled so that
// its squared length underflows in float (1e-20), in double (1e-160: a double denormal),
// overflows a float (1e19 is still finite in float, 1e200 is not), stays within RP_UNIT_TOL
// of unit (used as given) or just beyond it (renormalised), or is simply not unit.
std::vector<Vec3d> degenerate_versions(const Vec3d& w) {
    auto scaled = [&](double s) { return Vec3d{w[0] * s, w[1] * s, w[2] * s}; };
    return {
        {0, 0, 0},    {-0.0, -0.0, -0.0},    {kNaN, kNaN, kNaN}, {w[0], w[1], kNaN}, {kInf, 0, 0},
        {0, 0, kInf}, {-kInf, -kInf, -kInf}, scaled(1e-30),      scaled(1e-20),      scaled(1e-160),
        scaled(1e19), scaled(1e200),         scaled(1.0 + 5e-7), scaled(1.0 + 2e-6), scaled(7.5)};
}

std::vector<DirectionPair> stress_pairs(const Params& p, bool floatInputs, std::uint64_t seed) {
    PairBuilder b(p, floatInputs);
    Rng rng(seed);
    const double alpha = std::max(b.node().params().roughness, kMinAlpha);
    std::vector<DirectionPair> out;
    for (const glm::dvec3& wiL : incident_set(rng, alpha)) {
        const Vec3d wi = b.parent(wiL);
        auto add = [&](const Vec3d& wo) { out.push_back({wi, wo}); };
        // wo = wi exactly, and one ulp away in each component (both ways), and in all three.
        add(wi);
        for (int c = 0; c < 3; ++c)
            for (double toward : {-kInf, kInf}) {
                Vec3d w = wi;
                w[size_t(c)] = b.next(w[size_t(c)], toward);
                add(w);
            }
        add({b.next(wi[0], kInf), b.next(wi[1], kInf), b.next(wi[2], kInf)});
        add({b.next(wi[0], -kInf), b.next(wi[1], -kInf), b.next(wi[2], -kInf)});
        // The mirror direction and its ulp neighbours.
        const glm::dvec3 mirL(-wiL.x, -wiL.y, wiL.z);
        const Vec3d mir = b.parent(mirL);
        add(mir);
        for (int c = 0; c < 3; ++c) {
            Vec3d w = mir;
            w[size_t(c)] = b.next(w[size_t(c)], c == 2 ? -kInf : kInf);
            add(w);
        }
        // The opposite direction and the normal.
        add(b.parent(-wiL));
        add(b.parent({0, 0, 1}));
        // The lobes' own scale around wi and the mirror direction.
        for (double s : {0.5 * alpha, alpha, 3.0 * alpha, 9.0 * alpha, 1e-7, 1e-4, 1e-2, 0.3}) {
            add(b.parent(glm::normalize(wiL + glm::dvec3(s, 0, 0))));
            add(b.parent(glm::normalize(wiL + glm::dvec3(0, s, 0))));
            add(b.parent(glm::normalize(mirL + glm::dvec3(s, 0, 0))));
        }
        // Grazing and below-horizon outgoing directions, at wi's azimuth and its mirror's.
        const double phi = std::atan2(wiL.y, wiL.x) * 180.0 / M_PI;
        for (double z : {1e-7, kMinCos, next_d(kMinCos, 0.0), next_f(kMinCos, 1.0), 1e-40,
                         kDblDenorm, 0.0, -0.0, -1e-7}) {
            add(b.parent(grazing(z, phi)));
            add(b.parent(grazing(z, phi + 180.0)));
        }
        // Degenerate outgoing directions.
        for (const Vec3d& w : degenerate_versions(mir))
            add(b.round(glm::dvec3(w[0], w[1], w[2])));
        // Random ones over the hemisphere and below it.
        for (int k = 0; k < 6; ++k)
            add(b.parent(from_cos(rng.uniform(), 360.0 * rng.uniform())));
        add(b.parent(from_cos(-rng.uniform(), 360.0 * rng.uniform())));
    }
    // Degenerate incident directions, each with wo = its mirror and a regular direction.
    for (const Vec3d& w : degenerate_versions(b.parent(from_deg(40.0, 15.0)))) {
        const Vec3d wi = b.round(glm::dvec3(w[0], w[1], w[2]));
        out.push_back({wi, wi});
        out.push_back({wi, b.parent(from_deg(40.0, 195.0))});
        out.push_back({wi, b.parent(from_deg(20.0, 0.0))});
        out.push_back({b.parent(from_deg(40.0, 195.0)), wi});
    }
    return out;
}

// ---- Counting ---------------------------------------------------------------------------

// What one backend's sweep found.
struct Tally {
    std::string backend;
    long materials = 0;
    long evaluations = 0; // eval() calls, or (wi, wo) pairs answered by a GL backend
    long nonzero = 0;     // ... with a finite non-zero value (the sweep is not all zeros)
    long samples = 0;     // sample() calls (C++ backends)
    long nonempty = 0;    // ... that returned a direction
    long albedos = 0;     // albedo() calls (C++ backends)
    long values = 0;      // every number checked
    long nan = 0, inf = 0, negative = 0;
    // The guards of the contract: a zero, non-finite or below-horizon direction (or weight 0)
    // must give exactly zero values, a zero pdf and an empty sample.
    long guard = 0;
    // A sample whose f or pdf differs from eval / pdf at the same local direction, or from the
    // core's sample, or a non-empty sample with pdf <= 0.
    long inconsistent = 0;
    // Samples whose f or pdf differ from eval(wi, s.wo) beyond the tolerance only because the
    // frame's round trip (to_world in sample, to_local in eval) moved the direction by a few
    // ulp; at the same local direction they agree. Reported, not a failure.
    long round_trip = 0;
    double round_trip_max_rel = 0;
    double round_trip_max_ulps = 0;
    // sample() with u outside [0, 1)^3 (NaN, Inf, negative, > 1: outside the contract):
    // calls, and calls whose output has NaN, Inf or a negative value. Reported, not a failure.
    long oob_samples = 0, oob_bad = 0;
    double seconds = 0;
    // Every failure by cause, with the exact inputs of the first few.
    struct Cause {
        long count = 0;
        std::vector<std::string> examples;
    };
    std::map<std::string, Cause> causes;
    std::vector<std::string> oob_examples;
    static constexpr size_t kMaxExamples = 3;

    bool passed() const {
        return nan == 0 && inf == 0 && negative == 0 && guard == 0 && inconsistent == 0 &&
               oob_bad == 0;
    }
    void add(const Tally& o) {
        materials += o.materials;
        evaluations += o.evaluations;
        nonzero += o.nonzero;
        samples += o.samples;
        nonempty += o.nonempty;
        albedos += o.albedos;
        values += o.values;
        nan += o.nan;
        inf += o.inf;
        negative += o.negative;
        guard += o.guard;
        inconsistent += o.inconsistent;
        round_trip += o.round_trip;
        round_trip_max_rel = std::max(round_trip_max_rel, o.round_trip_max_rel);
        round_trip_max_ulps = std::max(round_trip_max_ulps, o.round_trip_max_ulps);
        oob_samples += o.oob_samples;
        oob_bad += o.oob_bad;
        for (const auto& [name, c] : o.causes) {
            Cause& mine = causes[name];
            mine.count += c.count;
            for (const std::string& e : c.examples)
                if (mine.examples.size() < kMaxExamples) mine.examples.push_back(e);
        }
        for (const std::string& e : o.oob_examples)
            if (oob_examples.size() < kMaxExamples) oob_examples.push_back(e);
    }
    // Records a failure (already counted in its column) under its cause.
    void failure(const std::string& cause, const std::string& what) {
        Cause& c = causes[cause];
        ++c.count;
        if (c.examples.size() < kMaxExamples) c.examples.push_back(what);
    }
};

// Counts one returned number; `where` describes it (called only when it is bad).
template <class Where>
bool check_value(Tally& t, double v, bool mayBeNegative, const char* call, const Where& where) {
    ++t.values;
    const char* bad = nullptr;
    if (std::isnan(v)) {
        ++t.nan;
        bad = "NaN";
    } else if (std::isinf(v)) {
        ++t.inf;
        bad = "Inf";
    } else if (!mayBeNegative && v < 0) {
        ++t.negative;
        bad = "negative";
    }
    if (bad)
        t.failure(std::string(bad) + " from " + call,
                  std::string(bad) + " value " + num(v) + " " + where());
    return bad == nullptr;
}

double rel_diff(double a, double b) {
    if (a == b) return 0.0;
    const double m = std::max(std::abs(a), std::abs(b));
    return std::abs(a - b) / m; // NaN when either is NaN: fails every comparison below
}

template <class Lobes>
double lobes_rel_diff(const Lobes& a, const Lobes& b) {
    double r = 0;
    for (int c = 0; c < 3; ++c)
        for (double d : {rel_diff(a.surface[c], b.surface[c]), rel_diff(a.retro[c], b.retro[c]),
                         rel_diff(a.diffuse[c], b.diffuse[c])})
            if (!(d <= r)) r = d;
    return r;
}

template <class Lobes>
bool lobes_identical(const Lobes& a, const Lobes& b) {
    for (int c = 0; c < 3; ++c)
        if (std::memcmp(&a.surface[c], &b.surface[c], sizeof a.surface[c]) ||
            std::memcmp(&a.retro[c], &b.retro[c], sizeof a.retro[c]) ||
            std::memcmp(&a.diffuse[c], &b.diffuse[c], sizeof a.diffuse[c]))
            return false;
    return true;
}

template <class V>
std::string vec_text(const V& v) {
    return describe(Vec3d{double(v.x), double(v.y), double(v.z)});
}

template <class Real>
struct Precision;
template <>
struct Precision<double> {
    static constexpr double rel = 1e-12;
};
template <>
struct Precision<float> {
    static constexpr double rel = 1e-5;
};

// A direction's round trip through an orthonormal frame (to_world in sample(), to_local in
// eval()) moves it by a few ulps; beyond these, a sample/eval difference is a failure.
constexpr double kFrameUlps = 8.0;
constexpr double kRoundTripUlps = 16.0;

// How far the node's frame (tangent, bitangent, normal) is from orthonormal, in ulps of its
// precision: the largest |e_i . e_j - delta_ij|.
template <class Node>
double frame_error_ulps(const Node& node) {
    using vec3 = typename Node::vec3;
    using Real = typename Node::real;
    const glm::dvec3 e[3] = {glm::dvec3(node.to_world(vec3(Real(1), Real(0), Real(0)))),
                             glm::dvec3(node.to_world(vec3(Real(0), Real(1), Real(0)))),
                             glm::dvec3(node.to_world(vec3(Real(0), Real(0), Real(1))))};
    double err = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            err = std::max(err, std::abs(glm::dot(e[i], e[j]) - (i == j ? 1.0 : 0.0)));
    return err / double(std::numeric_limits<Real>::epsilon());
}

// The C++ node of precision Real over one material: every pair evaluated, samples at every
// incident direction, albedos at a few.
template <class Real>
void sweep_cpp(const Params& p, const std::string& label, const std::vector<DirectionPair>& pairs,
               std::uint64_t seed, Tally& t) {
    using Node = PrismaticRetroreflector<Real>;
    using vec3 = typename Node::vec3;
    using Core = core<Real>;
    const Node node(p);
    const double frameUlps = frame_error_ulps(node);
    const auto& m = node.core_material();
    const bool weighted = m.weight > Real(0);
    const Real minCos = Real(kMinCos);
    const double tol = Precision<Real>::rel;
    auto toReal = [](const Vec3d& v) { return vec3(Real(v[0]), Real(v[1]), Real(v[2])); };
    // True when the contract lets (wi, wo) reflect: both directions finite, non-zero and at
    // least RP_MIN_COS above the horizon, and a positive weight.
    auto valid = [&](const vec3& w, vec3& local) {
        return node.to_local(w, local) && local.z >= minCos;
    };
    auto where = [&](const vec3& wi, const vec3* wo, const char* call) {
        std::string s = std::string("at ") + call + " wi = " + vec_text(wi);
        if (wo) s += ", wo = " + vec_text(*wo);
        return s + " of " + label + ": " + describe(p);
    };
    ++t.materials;

    // eval() at every pair.
    for (const DirectionPair& pr : pairs) {
        const vec3 wi = toReal(pr.wi), wo = toReal(pr.wo);
        const typename Node::Eval e = node.eval(wi, wo);
        ++t.evaluations;
        auto at = [&] { return where(wi, &wo, "eval"); };
        bool zero = true;
        const vec3 total = e.f.total();
        for (int c = 0; c < 3; ++c)
            for (Real v : {e.f.surface[c], e.f.retro[c], e.f.diffuse[c], total[c]}) {
                check_value(t, double(v), false, "eval", at);
                zero = zero && v == Real(0);
            }
        check_value(t, double(e.pdf), false, "eval", at);
        zero = zero && e.pdf == Real(0);
        if (!zero) ++t.nonzero;
        vec3 wiL, woL;
        if (!zero && !(weighted && valid(wi, wiL) && valid(wo, woL))) {
            ++t.guard;
            t.failure("guard: eval not zero",
                      "non-zero value where the guards require zero " + at());
        }
    }

    // sample() at every distinct incident direction.
    const Real below1 = std::nextafter(Real(1), Real(0));
    const Real tiny = std::numeric_limits<Real>::denorm_min();
    Rng rng(seed ^ 0x5a3b1e5ull);
    const DirectionPair* prev = nullptr;
    int incidentIndex = 0;
    for (const DirectionPair& pr : pairs) {
        if (prev && std::memcmp(prev->wi.data(), pr.wi.data(), sizeof pr.wi) == 0) continue;
        prev = &pr;
        const vec3 wi = toReal(pr.wi);
        vec3 wiL;
        const bool wiValid = weighted && valid(wi, wiL);
        // The lobe-selection boundaries of this wi.
        Real p0 = Real(0.5), p01 = Real(0.75);
        if (wiValid) {
            typename Core::incident s;
            Core::setup(m, wiL, s);
            p0 = s.lobeProb.x;
            p01 = s.lobeProb.x + s.lobeProb.y;
        }
        std::vector<vec3> us = {vec3(Real(0)),
                                vec3(Real(0.5)),
                                vec3(below1),
                                vec3(Real(1)),
                                vec3(tiny, Real(0.5), Real(0.25)),
                                vec3(below1, Real(0), Real(0.75)),
                                vec3(Real(0.3), Real(0.7), p0),
                                vec3(Real(0.3), Real(0.7), std::nextafter(p0, Real(0))),
                                vec3(Real(0.9), Real(0.1), std::nextafter(p0, Real(1))),
                                vec3(Real(0.6), Real(0.2), p01),
                                vec3(Real(0.6), Real(0.2), std::nextafter(p01, Real(0)))};
        for (int k = 0; k < 3; ++k)
            us.push_back(vec3(Real(rng.uniform()), Real(rng.uniform()), Real(rng.uniform())));
        for (vec3 u : us) {
            u = glm::clamp(u, vec3(Real(0)), vec3(Real(1)));
            const auto s = node.sample(wi, u);
            ++t.samples;
            if (!s) continue;
            ++t.nonempty;
            const vec3 wo = s->wo;
            auto at = [&] {
                return where(wi, &wo, "sample") + ", u = " + vec_text(u) + ", lobe " +
                       std::to_string(s->lobe);
            };
            if (!wiValid) {
                ++t.guard;
                t.failure("guard: sample not empty",
                          "non-empty sample where the guards require none " + at());
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                check_value(t, double(s->f.surface[c]), false, "sample", at);
                check_value(t, double(s->f.retro[c]), false, "sample", at);
                check_value(t, double(s->f.diffuse[c]), false, "sample", at);
                check_value(t, double(wo[c]), true, "sample", at);
            }
            check_value(t, double(s->pdf), false, "sample", at);
            if (!(s->pdf > Real(0))) {
                ++t.inconsistent;
                t.failure("sample: pdf not positive",
                          "non-empty sample with pdf " + num(double(s->pdf)) + " " + at());
                continue;
            }
            // The core's own sample at the same local wi: the node must return it unchanged.
            vec3 woL;
            typename Core::lobes r;
            Real pdf = 0;
            int lobe = -1;
            const bool coreOk = Core::sample(m, wiL, u, woL, r, pdf, lobe);
            const vec3 woWorld = node.to_world(woL);
            if (!coreOk || std::memcmp(&woWorld, &s->wo, sizeof woWorld) != 0 ||
                std::memcmp(&pdf, &s->pdf, sizeof pdf) != 0 || lobe != s->lobe ||
                !lobes_identical(r, typename Core::lobes{s->f.surface, s->f.retro, s->f.diffuse})) {
                ++t.inconsistent;
                t.failure("sample: the node's differs from the core's",
                          "the node's sample differs from the core's " + at());
                continue;
            }
            // eval and pdf at the same local direction.
            typename Core::lobes re;
            Real pe = 0;
            Core::eval(m, wiL, woL, re, pe);
            const double dCore = std::max(lobes_rel_diff(re, r), rel_diff(pe, pdf));
            if (!(dCore <= tol)) {
                ++t.inconsistent;
                t.failure("sample vs eval at the same local direction",
                          "sample and eval disagree by " + num(dCore) + " (relative) " + at());
                continue;
            }
            // eval(wi, s.wo) and pdf(wi, s.wo) through the node's frame.
            const typename Node::Eval e = node.eval(wi, wo);
            const Real pp = node.pdf(wi, wo);
            const double dNode = std::max(
                {lobes_rel_diff(typename Core::lobes{e.f.surface, e.f.retro, e.f.diffuse}, r),
                 rel_diff(e.pdf, pdf), rel_diff(pp, pdf)});
            if (dNode <= tol) continue;
            vec3 woL2;
            node.to_local(wo, woL2);
            const double ulps =
                double(glm::max(glm::abs(woL2.x - woL.x),
                                glm::max(glm::abs(woL2.y - woL.y), glm::abs(woL2.z - woL.z)))) /
                double(std::numeric_limits<Real>::epsilon());
            // Rounding explains the difference only when the frame is orthonormal to its
            // precision and the round trip moved the local direction by a few ulps.
            if (std::memcmp(&woL2, &woL, sizeof woL) == 0 || !(frameUlps <= kFrameUlps) ||
                !(ulps <= kRoundTripUlps) || !(dNode < kInf)) {
                ++t.inconsistent;
                t.failure(!(frameUlps <= kFrameUlps)
                              ? "sample vs eval(wi, s.wo): the frame is not orthonormal"
                          : !(ulps <= kRoundTripUlps)
                              ? "sample vs eval(wi, s.wo): the round trip moves wo by more than "
                                "16 ulp in an orthonormal frame"
                              : "sample vs eval(wi, s.wo)",
                          "sample and eval(wi, s.wo) disagree by " + num(dNode) +
                              " (the frame round trip moved the local direction by " + num(ulps) +
                              " ulp; frame orthonormal to " + num(frameUlps) + " ulp) " + at());
                continue;
            }
            ++t.round_trip;
            t.round_trip_max_rel = std::max(t.round_trip_max_rel, dNode);
            t.round_trip_max_ulps = std::max(t.round_trip_max_ulps, ulps);
        }
        // u outside the contract [0, 1)^3, at the first incident directions.
        if (incidentIndex++ < 4) {
            const Real nan = std::numeric_limits<Real>::quiet_NaN();
            const Real inf = std::numeric_limits<Real>::infinity();
            for (const vec3& u : {vec3(nan, Real(0.5), Real(0.5)), vec3(Real(0.5), nan, Real(0.99)),
                                  vec3(Real(0.5), nan, Real(0.5)), vec3(Real(0.5), nan, Real(0.01)),
                                  vec3(Real(0.5), Real(0.5), nan), vec3(inf, Real(0.5), Real(0.5)),
                                  vec3(Real(0.5), -inf, Real(0.99)), vec3(-inf, Real(-1), Real(2)),
                                  vec3(Real(-0.5), Real(1.5), Real(0.5))}) {
                const auto s = node.sample(wi, u);
                ++t.oob_samples;
                if (!s) continue;
                bool ok = std::isfinite(double(s->pdf)) && s->pdf > Real(0);
                for (int c = 0; c < 3; ++c)
                    for (Real v : {s->f.surface[c], s->f.retro[c], s->f.diffuse[c]})
                        ok = ok && std::isfinite(double(v)) && v >= Real(0);
                for (int c = 0; c < 3; ++c)
                    ok = ok && std::isfinite(double(s->wo[c]));
                if (!ok) {
                    ++t.oob_bad;
                    if (t.oob_examples.size() < Tally::kMaxExamples)
                        t.oob_examples.push_back(
                            "sample(wi = " + vec_text(wi) + ", u = " + vec_text(u) + ") = wo " +
                            vec_text(s->wo) + ", pdf " + num(double(s->pdf)) + ", lobe " +
                            std::to_string(s->lobe) + " of " + label);
                }
            }
        }
    }

    // albedo() with a small grid at a few incident directions.
    PairBuilder b(p, std::is_same<Real, float>::value);
    for (const glm::dvec3& wl : {glm::dvec3(0, 0, 1), from_deg(60.0, 10.0), from_deg(89.9, 0.0),
                                 grazing(1e-7, 30.0), glm::dvec3(kNaN, 0, 1)}) {
        const vec3 wi = toReal(b.parent(wl));
        const typename Node::Albedo a = node.albedo(wi, 8);
        ++t.albedos;
        auto at = [&] { return where(wi, nullptr, "albedo"); };
        bool zero = true;
        for (int c = 0; c < 3; ++c)
            for (Real v : {a.surface[c], a.retro[c], a.diffuse[c]}) {
                check_value(t, double(v), false, "albedo", at);
                zero = zero && v == Real(0);
            }
        vec3 wiL;
        if (!zero && !(weighted && valid(wi, wiL))) {
            ++t.guard;
            t.failure("guard: albedo not zero",
                      "non-zero albedo where the guards require zero " + at());
        }
    }
}

// A GL backend (glsl, materialx) over one material, through answer_query (the materials and
// directions go in unchecked: the JSON reader would reject most of them).
// The pairs go in queries of `batch` pairs (all of them when 0): a GL backend lays a query
// out over its work groups or render target by its size, and a fault may depend on the layout
// (the materialx backend's render target, read back by MaterialX's environment lookups, did).
void sweep_gl(const std::string& backend, const Params& p, const std::string& label,
              const std::vector<DirectionPair>& pairs, size_t batch, Tally& t) {
    json results = json::array();
    if (batch == 0) batch = pairs.size();
    for (size_t start = 0; start < pairs.size(); start += batch) {
        Query q;
        q.material = p;
        q.samples.assign(pairs.begin() + long(start),
                         pairs.begin() + long(std::min(pairs.size(), start + batch)));
        const json answer = answer_query(q, backend);
        for (const json& r : answer.at("results"))
            results.push_back(r);
    }
    if (results.size() != pairs.size())
        throw std::runtime_error(backend + " answered " + std::to_string(results.size()) +
                                 " results for " + std::to_string(pairs.size()) + " pairs");
    ++t.materials;
    const bool hasPdf = backend != "materialx";
    for (size_t k = 0; k < pairs.size(); ++k) {
        const json& r = results[k];
        ++t.evaluations;
        auto at = [&] {
            return "at wi = " + describe(pairs[k].wi) + ", wo = " + describe(pairs[k].wo) + " of " +
                   label + ": " + describe(p);
        };
        bool nonzero = false; // a finite non-zero value (NaN and Inf are counted above)
        auto number = [](const json& v) { return v.is_null() ? kNaN : v.get<double>(); };
        for (const char* key : {"surface", "retro", "diffuse", "f"})
            for (int c = 0; c < 3; ++c) {
                const double v = number(r.at(key).at(size_t(c)));
                check_value(t, v, false, "the backend", at);
                nonzero = nonzero || (std::isfinite(v) && v != 0.0);
            }
        if (hasPdf) {
            // The JSON answer writes a NaN pdf as null: null counts as NaN here.
            const double v = number(r.at("pdf"));
            check_value(t, v, false, "the backend (pdf)", at);
            nonzero = nonzero || (std::isfinite(v) && v != 0.0);
        }
        // Zero and non-finite directions (as the backend's floats see them) give zero. The
        // materialx backend is the exception for a zero wo: it places the eye at wo and shades
        // the fragment at the origin, so a zero wo puts the eye on the fragment and the view
        // direction MaterialX computes (normalize(eye - position), the position off the origin
        // by its interpolation's rounding) is not wo: it is not an input the node sees.
        auto zeroDir = [](const Vec3d& w) {
            return float(w[0]) == 0.0f && float(w[1]) == 0.0f && float(w[2]) == 0.0f;
        };
        auto nonFinite = [](const Vec3d& w) {
            return !std::isfinite(float(w[0])) || !std::isfinite(float(w[1])) ||
                   !std::isfinite(float(w[2]));
        };
        const bool mustBeZero = zeroDir(pairs[k].wi) || nonFinite(pairs[k].wi) ||
                                nonFinite(pairs[k].wo) ||
                                (backend != "materialx" && zeroDir(pairs[k].wo));
        if (nonzero) ++t.nonzero;
        if (nonzero && mustBeZero) {
            ++t.guard;
            t.failure("guard: not zero for a zero or non-finite direction",
                      "non-zero value for a zero or non-finite direction " + at());
        }
    }
}

// ---- The sweep --------------------------------------------------------------------------

bool float_inputs(const std::string& backend) {
    return backend != "cpp-double";
}

std::uint64_t pair_seed(long material) {
    return 0xC0FFEEull * 0x9E3779B97F4A7C15ull + std::uint64_t(material);
}

struct Options {
    long cpp_evaluations = kCppEvaluations;
    long gl_evaluations = kGlEvaluations;
    int threads = 0; // 0: one per hardware thread
    // Every pair_stride-th direction pair of each material (offset by the material's index):
    // a smaller sweep over the same materials (the bounded test); 1 in the full sweep.
    int pair_stride = 1;
};

// The pairs material `index` uses under the options.
std::vector<DirectionPair> material_pairs(const Params& p, long index, bool floatInputs,
                                          const Options& opt) {
    std::vector<DirectionPair> all = stress_pairs(p, floatInputs, pair_seed(index));
    if (opt.pair_stride <= 1) return all;
    std::vector<DirectionPair> out;
    for (size_t k = size_t(index % opt.pair_stride); k < all.size(); k += size_t(opt.pair_stride))
        out.push_back(all[k]);
    return out;
}

Tally run_backend(const std::string& backend, const Options& opt) {
    Tally total;
    total.backend = backend;
    const auto t0 = std::chrono::steady_clock::now();
    const bool isCpp = backend == "cpp-double" || backend == "cpp-float";
    const long target = isCpp ? opt.cpp_evaluations : opt.gl_evaluations;
    if (isCpp) {
        // Materials in parallel, each into its own tally, merged in order.
        // Every material has the same number of pairs (at least perMaterial under a stride).
        const size_t perMaterial =
            stress_pairs(Params(), true, 0).size() / size_t(std::max(1, opt.pair_stride));
        const long count = long((size_t(target) + perMaterial - 1) / perMaterial);
        std::vector<Tally> parts(static_cast<size_t>(count));
        std::atomic<long> nextIndex{0};
        std::mutex errorMutex;
        std::string error;
        auto work = [&] {
            for (long i; (i = nextIndex++) < count;) {
                try {
                    std::string label;
                    const Params p = material(i, &label);
                    const auto pairs = material_pairs(p, i, float_inputs(backend), opt);
                    if (backend == "cpp-double")
                        sweep_cpp<double>(p, label, pairs, pair_seed(i), parts[size_t(i)]);
                    else
                        sweep_cpp<float>(p, label, pairs, pair_seed(i), parts[size_t(i)]);
                } catch (const std::exception& e) {
                    std::lock_guard<std::mutex> lock(errorMutex);
                    if (error.empty()) error = e.what();
                }
            }
        };
        const int n =
            opt.threads > 0 ? opt.threads : int(std::max(1u, std::thread::hardware_concurrency()));
        std::vector<std::thread> threads;
        for (int k = 1; k < n; ++k)
            threads.emplace_back(work);
        work();
        for (std::thread& th : threads)
            th.join();
        if (!error.empty()) throw std::runtime_error(error);
        for (const Tally& part : parts)
            total.add(part);
    } else {
        for (long i = 0; total.evaluations < target; ++i) {
            std::string label;
            const Params p = material(i, &label);
            // One query per material, or batches of 5, 61, 256 or 700 pairs, in turn.
            const size_t batches[] = {0, 5, 61, 256, 700};
            sweep_gl(backend, p, label, material_pairs(p, i, true, opt), batches[i % 5], total);
        }
    }
    total.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return total;
}

void print_header(FILE* out) {
    std::fprintf(out, "%-11s %9s %12s %10s %8s %12s %7s %7s %8s %6s %12s %10s %8s  %s\n", "backend",
                 "materials", "evaluations", "samples", "albedos", "values", "NaN", "Inf",
                 "negative", "guard", "inconsistent", "round-trip", "seconds", "result");
}

void print_row(FILE* out, const Tally& t) {
    const bool cpp = t.samples > 0;
    auto opt = [&](long v) { return cpp ? std::to_string(v) : std::string("-"); };
    std::fprintf(out, "%-11s %9ld %12ld %10s %8s %12ld %7ld %7ld %8ld %6ld %12s %10s %8.1f  %s\n",
                 t.backend.c_str(), t.materials, t.evaluations, opt(t.samples).c_str(),
                 opt(t.albedos).c_str(), t.values, t.nan, t.inf, t.negative, t.guard,
                 opt(t.inconsistent).c_str(), opt(t.round_trip).c_str(), t.seconds,
                 t.passed() ? "pass" : "FAIL");
    std::fflush(out);
}

void print_notes(FILE* out, const std::vector<Tally>& tallies) {
    for (const Tally& t : tallies) {
        std::fprintf(out, "%s: %.1f%% of the evaluations have a non-zero value\n",
                     t.backend.c_str(),
                     t.evaluations ? 100.0 * double(t.nonzero) / double(t.evaluations) : 0.0);
        if (t.round_trip > 0)
            std::fprintf(out,
                         "%s: %ld samples differ from eval(wi, s.wo) only through the frame's "
                         "round trip (the local direction moved by up to %.3g ulp; up to %.3g "
                         "relative); at the same local direction they agree\n",
                         t.backend.c_str(), t.round_trip, t.round_trip_max_ulps,
                         t.round_trip_max_rel);
        if (t.oob_samples > 0)
            std::fprintf(out,
                         "%s: u outside [0, 1)^3 (clamped by sample()): %ld samples, %ld with a "
                         "NaN, Inf or negative output (required: 0)\n",
                         t.backend.c_str(), t.oob_samples, t.oob_bad);
        for (const std::string& e : t.oob_examples)
            std::fprintf(out, "  %s\n", e.c_str());
        for (const auto& [cause, c] : t.causes) {
            std::fprintf(out, "%s FAILURES (%ld): %s\n", t.backend.c_str(), c.count, cause.c_str());
            for (const std::string& e : c.examples)
                std::fprintf(out, "  %s\n", e.c_str());
        }
    }
}

int run(const std::vector<std::string>& backends, const Options& opt, FILE* out) {
    const std::vector<std::string> known = backend_names();
    for (const std::string& b : backends)
        if (std::find(known.begin(), known.end(), b) == known.end()) {
            std::string names;
            for (const std::string& n : known)
                names += (names.empty() ? "" : ", ") + n;
            std::fprintf(stderr,
                         "retroprism check --stress: unknown backend \"%s\" (backends: %s)\n",
                         b.c_str(), names.c_str());
            return 2;
        }
    const size_t perMaterial = stress_pairs(Params(), true, 0).size();
    std::fprintf(out,
                 "adversarial sweep: %zu direction pairs per material (%ld enum/boolean "
                 "combinations, %zu single-input hard values, then random hard combinations); "
                 "required: no NaN, Inf, negative value, guard violation or inconsistency\n",
                 perMaterial, combination_count(), single_mutations().size());
    print_header(out);
    std::vector<Tally> tallies;
    for (const std::string& b : backends) {
        tallies.push_back(run_backend(b, opt));
        print_row(out, tallies.back());
    }
    print_notes(out, tallies);
    bool ok = true;
    for (const Tally& t : tallies)
        ok = ok && t.passed();
    std::fprintf(out, "stress: %s\n", ok ? "pass" : "FAIL");
    return ok ? 0 : 1;
}

} // namespace stress

int run_stress(const std::vector<std::string>& backends) {
    return stress::run(backends, stress::Options(), stdout);
}

} // namespace retroprism
