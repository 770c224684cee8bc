// stress.cpp: the adversarial sweep of a backend (`retroprism check --stress`).
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
// Random choices come from util's Rng, one stream per material (its index), so the sweep does
// not depend on the thread count.
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
// Sizes (Options): 1e7 evaluations for each C++ backend (cpp-batch included: one batch per
// material, checked as a GL backend's answers) and 1e6 for each GL one, batched per material
// (about 2500 pairs each). Measured on two cores with llvmpipe: cpp-double 5 s,
// cpp-float 4 s, glsl 2 s, materialx 35 s on an idle machine, up to four times that under load.
#include "stress.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "backend.h"
#include "parallel.h"
#include "rng.h"

namespace retroprism {
namespace stress {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDblMax = std::numeric_limits<double>::max();
constexpr double kDblDenorm = std::numeric_limits<double>::denorm_min();
constexpr double kDblEps = std::numeric_limits<double>::epsilon();
constexpr double kFltEps = double(std::numeric_limits<float>::epsilon());
const double kMinAlpha = f64::RP_MIN_ALPHA;
const double kMinCos = f64::RP_MIN_COS;

// The seeds of the sweep's random streams (each Rng's stream is the material's index): the
// random materials, their direction pairs, the C++ backends' sample() arguments.
constexpr std::uint64_t kMaterialSeed = 0x5eed0000ull;
constexpr std::uint64_t kPairSeed = 0xC0FFEEull;
constexpr std::uint64_t kSampleSeed = 0x5a3b1e5ull;

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
    if (name == "dihedral_error") {
        // 0 switches the ring off; the smallest rings are far inside the narrowest lobe, the
        // largest (60 arcmin at roughness 1e-4) hundreds of lobe widths wide.
        return {0.0, 1e-30, 1e-7, -1e-7, 0.01, 3.0, 59.999999, 60.000001, 100.0, 1e10, -1e10};
    }
    if (name == "dihedral_spread") {
        // 0 leaves the lobe's widths alone; the largest spreads widen the narrowest lobe by
        // hundreds of its widths.
        return {0.0, 1e-30, 1e-7, -1e-7, 0.01, 3.0, 59.999999, 60.000001, 100.0, 1e10, -1e10};
    }
    if (name == "cant_angle") {
        return {-30.0, 30.0, -30.000001, 30.000001, 1e-30, -1e-7, 15.0, -45.0, 90.0, 1e10, -1e10};
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

// A random material (number `index` of them): the inputs of a random combination each at a hard
// value (probability 0.4) or a random in-range value.
Params random_material(long index) {
    const long combos = combination_count();
    Rng rng(kMaterialSeed, std::uint64_t(index));
    Params p = combination(long(rng.index(size_t(combos))));
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
    return p;
}

// The single-input hard values, made once.
const std::vector<Mutation>& singles() {
    static const std::vector<Mutation> s = single_mutations();
    return s;
}

} // namespace

Params material(long index, std::string* label) {
    const long combos = combination_count();
    if (index < combos) {
        if (label) *label = "combination " + std::to_string(index);
        return combination(index);
    }
    index -= combos;
    if (index < long(singles().size())) {
        Params p = combination((index * 7) % combos);
        singles()[size_t(index)].apply(p);
        if (label)
            *label = "combination " + std::to_string((index * 7) % combos) + " with " +
                     singles()[size_t(index)].label;
        return p;
    }
    index -= long(singles().size());
    if (label) *label = "random material " + std::to_string(index);
    return random_material(index);
}

long hard_material_count() {
    return combination_count() + long(singles().size());
}

namespace {

// All inputs of a material, exactly (for reports).
std::string describe(const Params& p) {
    std::string s = "{";
    auto add = [&](const std::string& k, const std::string& v) {
        s += (s.size() > 1 ? ", " : "") + k + ": " + v;
    };
    auto v3 = [](const std::array<double, 3>& v) {
        return "[" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + "]";
    };
    for_each_input(p, [&](const ParamInfo& info, const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>)
            add(info.name, num(v));
        else if constexpr (std::is_same_v<T, Color3>)
            add(info.name, v3(v));
        else if constexpr (std::is_same_v<T, int>)
            add(info.name, std::to_string(v));
        else
            add(info.name, v ? "true" : "false");
    });
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

} // namespace

std::vector<DirectionPair> stress_pairs(const Params& p, bool floatInputs, std::uint64_t stream) {
    PairBuilder b(p, floatInputs);
    Rng rng(kPairSeed, stream);
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

namespace {

// ---- Counting ---------------------------------------------------------------------------

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

// The C++ node of precision Real over one material: every pair evaluated, samples at every
// incident direction, albedos at a few; everything counted into one tally.
template <class Real>
class CppSweep {
  public:
    using Node = PrismaticRetroreflector<Real>;
    using vec3 = typename Node::vec3;
    using Core = core<Real>;

    CppSweep(const Params& p, const std::string& label, Tally& t)
        : p_(p), label_(label), t_(t), node_(p), m_(node_.core_material()),
          frameUlps_(frame_error_ulps(node_)), weighted_(m_.weight > Real(0)) {}

    // The pairs of the material; `rng` gives the random u of sample().
    void run(const std::vector<DirectionPair>& pairs, Rng& rng) {
        ++t_.materials;
        for (const DirectionPair& pr : pairs)
            eval_pair(to_real(pr.wi), to_real(pr.wo));
        // sample() at every distinct incident direction (the pairs of one wi are adjacent), and
        // with u outside its contract at the first four.
        const DirectionPair* prev = nullptr;
        int incidentIndex = 0;
        for (const DirectionPair& pr : pairs) {
            if (prev && std::memcmp(prev->wi.data(), pr.wi.data(), sizeof pr.wi) == 0) continue;
            prev = &pr;
            const vec3 wi = to_real(pr.wi);
            sample_incident(wi, rng);
            if (incidentIndex++ < 4) sample_outside_contract(wi);
        }
        albedos();
    }

  private:
    static vec3 to_real(const Vec3d& v) { return vec3(Real(v[0]), Real(v[1]), Real(v[2])); }

    // True when the contract lets w reflect: finite, non-zero and at least RP_MIN_COS above the
    // horizon (a pair reflects when both do and the weight is positive).
    bool valid(const vec3& w, vec3& local) const {
        return node_.to_local(w, local) && local.z >= Real(kMinCos);
    }

    std::string where(const vec3& wi, const vec3* wo, const char* call) const {
        std::string s = std::string("at ") + call + " wi = " + vec_text(wi);
        if (wo) s += ", wo = " + vec_text(*wo);
        return s + " of " + label_ + ": " + describe(p_);
    }

    // eval() at one pair: finite, non-negative, zero where the guards say so.
    void eval_pair(const vec3& wi, const vec3& wo) {
        const typename Node::Eval e = node_.eval(wi, wo);
        ++t_.evaluations;
        auto at = [&] { return where(wi, &wo, "eval"); };
        bool zero = true;
        const vec3 total = e.f.total();
        for (int c = 0; c < 3; ++c)
            for (Real v : {e.f.surface[c], e.f.retro[c], e.f.diffuse[c], total[c]}) {
                check_value(t_, double(v), false, "eval", at);
                zero = zero && v == Real(0);
            }
        check_value(t_, double(e.pdf), false, "eval", at);
        zero = zero && e.pdf == Real(0);
        if (!zero) ++t_.nonzero;
        vec3 wiL, woL;
        if (!zero && !(weighted_ && valid(wi, wiL) && valid(wo, woL))) {
            ++t_.guard;
            t_.failure("guard: eval not zero",
                       "non-zero value where the guards require zero " + at());
        }
    }

    // The u of sample() at one wi: 0, 1 and one ulp below, a denormal, the lobe-selection
    // boundaries of wi (p0 and p0 + p1) and their neighbours, three random ones.
    std::vector<vec3> contract_us(bool wiValid, const vec3& wiL, Rng& rng) const {
        const Real below1 = std::nextafter(Real(1), Real(0));
        const Real tiny = std::numeric_limits<Real>::denorm_min();
        Real p0 = Real(0.5), p01 = Real(0.75);
        if (wiValid) {
            typename Core::incident s;
            Core::setup(m_, wiL, s);
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
        for (vec3& u : us)
            u = glm::clamp(u, vec3(Real(0)), vec3(Real(1)));
        return us;
    }

    void sample_incident(const vec3& wi, Rng& rng) {
        vec3 wiL;
        const bool wiValid = weighted_ && valid(wi, wiL);
        for (const vec3& u : contract_us(wiValid, wiL, rng))
            check_sample(wi, wiValid, wiL, u);
    }

    // One sample() with u in its contract: empty where the guards say so; otherwise finite,
    // non-negative, a positive pdf, the core's own sample, and equal to eval and pdf at the
    // sampled direction.
    void check_sample(const vec3& wi, bool wiValid, const vec3& wiL, const vec3& u) {
        const auto s = node_.sample(wi, u);
        ++t_.samples;
        if (!s) return;
        ++t_.nonempty;
        const vec3 wo = s->wo;
        auto at = [&] {
            return where(wi, &wo, "sample") + ", u = " + vec_text(u) + ", lobe " +
                   std::to_string(s->lobe);
        };
        if (!wiValid) {
            ++t_.guard;
            t_.failure("guard: sample not empty",
                       "non-empty sample where the guards require none " + at());
            return;
        }
        for (int c = 0; c < 3; ++c) {
            check_value(t_, double(s->f.surface[c]), false, "sample", at);
            check_value(t_, double(s->f.retro[c]), false, "sample", at);
            check_value(t_, double(s->f.diffuse[c]), false, "sample", at);
            check_value(t_, double(wo[c]), true, "sample", at);
        }
        check_value(t_, double(s->pdf), false, "sample", at);
        if (!(s->pdf > Real(0))) {
            ++t_.inconsistent;
            t_.failure("sample: pdf not positive",
                       "non-empty sample with pdf " + num(double(s->pdf)) + " " + at());
            return;
        }
        // The core's own sample at the same local wi: the node must return it unchanged.
        vec3 woL;
        typename Core::lobes r;
        Real pdf = 0;
        int lobe = -1;
        const bool coreOk = Core::sample(m_, wiL, u, woL, r, pdf, lobe);
        const vec3 woWorld = node_.to_world(woL);
        if (!coreOk || std::memcmp(&woWorld, &s->wo, sizeof woWorld) != 0 ||
            std::memcmp(&pdf, &s->pdf, sizeof pdf) != 0 || lobe != s->lobe ||
            !lobes_identical(r, typename Core::lobes{s->f.surface, s->f.retro, s->f.diffuse})) {
            ++t_.inconsistent;
            t_.failure("sample: the node's differs from the core's",
                       "the node's sample differs from the core's " + at());
            return;
        }
        // eval and pdf at the same local direction.
        typename Core::lobes re;
        Real pe = 0;
        Core::eval(m_, wiL, woL, re, pe);
        const double dCore = std::max(lobes_rel_diff(re, r), rel_diff(pe, pdf));
        if (!(dCore <= Precision<Real>::rel)) {
            ++t_.inconsistent;
            t_.failure("sample vs eval at the same local direction",
                       "sample and eval disagree by " + num(dCore) + " (relative) " + at());
            return;
        }
        compare_through_frame(wi, wo, woL, r, pdf, at);
    }

    // eval(wi, s.wo) and pdf(wi, s.wo) through the node's frame against the sample (lobes r,
    // pdf, at local direction woL): equal within the tolerance, or different only by the
    // frame's round trip (counted apart).
    template <class Where>
    void compare_through_frame(const vec3& wi, const vec3& wo, const vec3& woL,
                               const typename Core::lobes& r, Real pdf, const Where& at) {
        const typename Node::Eval e = node_.eval(wi, wo);
        const Real pp = node_.pdf(wi, wo);
        const double dNode =
            std::max({lobes_rel_diff(typename Core::lobes{e.f.surface, e.f.retro, e.f.diffuse}, r),
                      rel_diff(e.pdf, pdf), rel_diff(pp, pdf)});
        if (dNode <= Precision<Real>::rel) return;
        vec3 woL2;
        node_.to_local(wo, woL2);
        const double ulps =
            double(glm::max(glm::abs(woL2.x - woL.x),
                            glm::max(glm::abs(woL2.y - woL.y), glm::abs(woL2.z - woL.z)))) /
            double(std::numeric_limits<Real>::epsilon());
        // Rounding explains the difference only when the frame is orthonormal to its
        // precision and the round trip moved the local direction by a few ulps.
        if (std::memcmp(&woL2, &woL, sizeof woL) == 0 || !(frameUlps_ <= kFrameUlps) ||
            !(ulps <= kRoundTripUlps) || !(dNode < kInf)) {
            ++t_.inconsistent;
            t_.failure(!(frameUlps_ <= kFrameUlps)
                           ? "sample vs eval(wi, s.wo): the frame is not orthonormal"
                       : !(ulps <= kRoundTripUlps)
                           ? "sample vs eval(wi, s.wo): the round trip moves wo by more than "
                             "16 ulp in an orthonormal frame"
                           : "sample vs eval(wi, s.wo)",
                       "sample and eval(wi, s.wo) disagree by " + num(dNode) +
                           " (the frame round trip moved the local direction by " + num(ulps) +
                           " ulp; frame orthonormal to " + num(frameUlps_) + " ulp) " + at());
            return;
        }
        ++t_.round_trip;
        t_.round_trip_max_rel = std::max(t_.round_trip_max_rel, dNode);
        t_.round_trip_max_ulps = std::max(t_.round_trip_max_ulps, ulps);
    }

    // sample() with u outside the contract [0, 1)^3 (NaN, Inf, negative, > 1): sample() clamps
    // u, so a sample must still be finite with a positive pdf and non-negative values.
    void sample_outside_contract(const vec3& wi) {
        const Real nan = std::numeric_limits<Real>::quiet_NaN();
        const Real inf = std::numeric_limits<Real>::infinity();
        for (const vec3& u : {vec3(nan, Real(0.5), Real(0.5)), vec3(Real(0.5), nan, Real(0.99)),
                              vec3(Real(0.5), nan, Real(0.5)), vec3(Real(0.5), nan, Real(0.01)),
                              vec3(Real(0.5), Real(0.5), nan), vec3(inf, Real(0.5), Real(0.5)),
                              vec3(Real(0.5), -inf, Real(0.99)), vec3(-inf, Real(-1), Real(2)),
                              vec3(Real(-0.5), Real(1.5), Real(0.5))}) {
            const auto s = node_.sample(wi, u);
            ++t_.oob_samples;
            if (!s) continue;
            bool ok = std::isfinite(double(s->pdf)) && s->pdf > Real(0);
            for (int c = 0; c < 3; ++c)
                for (Real v : {s->f.surface[c], s->f.retro[c], s->f.diffuse[c]})
                    ok = ok && std::isfinite(double(v)) && v >= Real(0);
            for (int c = 0; c < 3; ++c)
                ok = ok && std::isfinite(double(s->wo[c]));
            if (!ok) {
                ++t_.oob_bad;
                if (t_.oob_examples.size() < Tally::kMaxExamples)
                    t_.oob_examples.push_back("sample(wi = " + vec_text(wi) +
                                              ", u = " + vec_text(u) + ") = wo " + vec_text(s->wo) +
                                              ", pdf " + num(double(s->pdf)) + ", lobe " +
                                              std::to_string(s->lobe) + " of " + label_);
            }
        }
    }

    // albedo() with a small grid at a few incident directions: finite, non-negative, zero
    // where the guards say so.
    void albedos() {
        const PairBuilder b(p_, std::is_same<Real, float>::value);
        for (const glm::dvec3& wl : {glm::dvec3(0, 0, 1), from_deg(60.0, 10.0), from_deg(89.9, 0.0),
                                     grazing(1e-7, 30.0), glm::dvec3(kNaN, 0, 1)}) {
            const vec3 wi = to_real(b.parent(wl));
            const typename Node::Albedo a = node_.albedo(wi, 8);
            ++t_.albedos;
            auto at = [&] { return where(wi, nullptr, "albedo"); };
            bool zero = true;
            for (int c = 0; c < 3; ++c)
                for (Real v : {a.surface[c], a.retro[c], a.diffuse[c]}) {
                    check_value(t_, double(v), false, "albedo", at);
                    zero = zero && v == Real(0);
                }
            vec3 wiL;
            if (!zero && !(weighted_ && valid(wi, wiL))) {
                ++t_.guard;
                t_.failure("guard: albedo not zero",
                           "non-zero albedo where the guards require zero " + at());
            }
        }
    }

    const Params& p_;
    const std::string& label_;
    Tally& t_;
    const Node node_;
    const typename Core::material& m_;
    const double frameUlps_;
    const bool weighted_;
};

// True when a direction is zero or non-finite as a GL backend's floats see it.
bool zero_direction(const Vec3d& w) {
    return float(w[0]) == 0.0f && float(w[1]) == 0.0f && float(w[2]) == 0.0f;
}
bool non_finite_direction(const Vec3d& w) {
    return !std::isfinite(float(w[0])) || !std::isfinite(float(w[1])) ||
           !std::isfinite(float(w[2]));
}

// A GL backend (glsl, materialx) over one material, through Backend::evaluate (the materials
// and directions go in unchecked: the JSON reader would reject most of them).
// The pairs go in batches of `batch` pairs (all of them when 0): a GL backend lays a batch out
// over its work groups or render target by its size, and a fault may depend on the layout (the
// materialx backend's render target, read back by MaterialX's environment lookups, did).
void sweep_gl(Backend& gl, const Params& p, const std::string& label,
              const std::vector<DirectionPair>& pairs, size_t batch, Tally& t) {
    std::vector<BackendResult> results;
    if (batch == 0) batch = pairs.size();
    for (size_t start = 0; start < pairs.size(); start += batch) {
        const std::vector<DirectionPair> part(pairs.begin() + long(start),
                                              pairs.begin() +
                                                  long(std::min(pairs.size(), start + batch)));
        for (const BackendResult& r : gl.evaluate(p, part))
            results.push_back(r);
    }
    if (results.size() != pairs.size())
        throw std::runtime_error(gl.name() + " answered " + std::to_string(results.size()) +
                                 " results for " + std::to_string(pairs.size()) + " pairs");
    ++t.materials;
    // A MaterialX shader has no pdf (BackendResult::pdf is NaN).
    const bool materialx = gl.name() == "materialx";
    for (size_t k = 0; k < pairs.size(); ++k) {
        const BackendResult& r = results[k];
        ++t.evaluations;
        auto at = [&] {
            return "at wi = " + describe(pairs[k].wi) + ", wo = " + describe(pairs[k].wo) + " of " +
                   label + ": " + describe(p);
        };
        bool nonzero = false; // a finite non-zero value (NaN and Inf are counted apart)
        for (const std::array<double, 3>* rgb : {&r.surface, &r.retro, &r.diffuse, &r.f})
            for (double v : *rgb) {
                check_value(t, v, false, "the backend", at);
                nonzero = nonzero || (std::isfinite(v) && v != 0.0);
            }
        if (!materialx) {
            check_value(t, r.pdf, false, "the backend (pdf)", at);
            nonzero = nonzero || (std::isfinite(r.pdf) && r.pdf != 0.0);
        }
        // Zero and non-finite directions give zero. The materialx backend is the exception for
        // a zero wo: it places the eye at wo and shades the fragment at the origin, so a zero wo
        // puts the eye on the fragment and the view direction MaterialX computes
        // (normalize(eye - position), the position off the origin by its interpolation's
        // rounding) is not wo: it is not an input the node sees.
        const bool mustBeZero = zero_direction(pairs[k].wi) || non_finite_direction(pairs[k].wi) ||
                                non_finite_direction(pairs[k].wo) ||
                                (!materialx && zero_direction(pairs[k].wo));
        if (nonzero) ++t.nonzero;
        if (nonzero && mustBeZero) {
            ++t.guard;
            t.failure("guard: not zero for a zero or non-finite direction",
                      "non-zero value for a zero or non-finite direction " + at());
        }
    }
}

// ---- The sweep --------------------------------------------------------------------------

size_t pairs_per_material() {
    static const size_t n = stress_pairs(Params(), true, 0).size();
    return n;
}

// The pairs material `index` uses under the options.
std::vector<DirectionPair> material_pairs(const Params& p, long index, bool floatInputs,
                                          const Options& opt) {
    std::vector<DirectionPair> all = stress_pairs(p, floatInputs, std::uint64_t(index));
    if (opt.pair_stride <= 1) return all;
    std::vector<DirectionPair> out;
    for (size_t k = size_t(index % opt.pair_stride); k < all.size(); k += size_t(opt.pair_stride))
        out.push_back(all[k]);
    return out;
}

// A C++ backend: materials in parallel, each into its own tally, merged in order.
template <class Real>
Tally sweep_cpp(const Options& opt) {
    const bool floatInputs = std::is_same<Real, float>::value;
    // Every material has the same number of pairs (at least perMaterial under a stride).
    const size_t perMaterial = pairs_per_material() / size_t(std::max(1, opt.pair_stride));
    const size_t count = (size_t(opt.cpp_evaluations) + perMaterial - 1) / perMaterial;
    std::vector<Tally> parts(count);
    std::mutex errorMutex;
    std::string error;
    parallel_for(count, opt.threads, [&](size_t i) {
        try {
            std::string label;
            const Params p = material(long(i), &label);
            Rng rng(kSampleSeed, i);
            CppSweep<Real>(p, label, parts[i])
                .run(material_pairs(p, long(i), floatInputs, opt), rng);
        } catch (const std::exception& e) {
            const std::lock_guard<std::mutex> lock(errorMutex);
            if (error.empty()) error = e.what();
        }
    });
    if (!error.empty()) throw std::runtime_error(error);
    Tally total;
    for (const Tally& part : parts)
        total.add(part);
    return total;
}

// The batch backend (cpp-batch): materials in parallel as sweep_cpp, each one batch checked as
// a GL backend's answers (values and guards) into its own tally, merged in order.
Tally sweep_batch_backend(const Options& opt) {
    Backend& batch = backend("cpp-batch");
    const size_t perMaterial = pairs_per_material() / size_t(std::max(1, opt.pair_stride));
    const size_t count = (size_t(opt.cpp_evaluations) + perMaterial - 1) / perMaterial;
    std::vector<Tally> parts(count);
    parallel_for(count, opt.threads, [&](size_t i) {
        std::string label;
        const Params p = material(long(i), &label);
        sweep_gl(batch, p, label, material_pairs(p, long(i), true, opt), 0, parts[i]);
    });
    Tally total;
    for (const Tally& part : parts)
        total.add(part);
    return total;
}

// A GL backend: materials in turn, one batch per material or batches of 5, 61, 256 or 700
// pairs, in turn.
Tally sweep_gl_backend(Backend& gl, const Options& opt) {
    Tally total;
    const size_t batches[] = {0, 5, 61, 256, 700};
    for (long i = 0; total.evaluations < opt.gl_evaluations; ++i) {
        std::string label;
        const Params p = material(i, &label);
        sweep_gl(gl, p, label, material_pairs(p, i, true, opt), batches[i % 5], total);
    }
    return total;
}

} // namespace

Options quick_options(const std::string& backend) {
    return quick_options(backend, backend == "materialx" ? 13 : 7);
}

Options quick_options(const std::string& backend, int pairStride) {
    Options opt;
    opt.pair_stride = std::max(1, pairStride);
    const long materials = hard_material_count();
    const long perMaterial = long(pairs_per_material()) / opt.pair_stride + 1;
    opt.cpp_evaluations = std::max(1000000L, materials * perMaterial);
    opt.gl_evaluations = backend == "materialx" ? materials * perMaterial
                                                : std::max(500000L, materials * perMaterial);
    return opt;
}

Options sized_options(long cppEvaluations) {
    Options opt;
    opt.cpp_evaluations = cppEvaluations;
    opt.gl_evaluations = std::max(1L, cppEvaluations / 10);
    return opt;
}

Tally sweep_backend(const std::string& name, const Options& opt) {
    const auto t0 = std::chrono::steady_clock::now();
    Tally t = name == "cpp-double"  ? sweep_cpp<double>(opt)
              : name == "cpp-float" ? sweep_cpp<float>(opt)
              : name == "cpp-batch" ? sweep_batch_backend(opt)
                                    : sweep_gl_backend(backend(name), opt); // InputError if unknown
    t.backend = name;
    t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return t;
}

Coverage coverage() {
    return {pairs_per_material(), combination_count(), long(singles().size())};
}

} // namespace stress
} // namespace retroprism
