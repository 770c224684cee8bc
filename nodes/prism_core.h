// prism_core.h: the C++ instantiations of the model's math core (prism_core.inc), in float
// (namespace retroprism::f32) and double (retroprism::f64). The core is written once in the
// common subset of C++ and GLSL; this header supplies its C++ prelude.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#define RP_FN inline
// The evaluation path is one function: its small helpers always inlined (their incident state
// then lives in registers and eval drops what it does not use), the rare reciprocal-form
// branches kept out of it.
// Sanitizer builds (-DRP_NO_FORCED_INLINE, scripts/sanitize.sh) leave inlining to the compiler:
// instrumented, the forced inlining made this core the slowest part of their build.
#ifdef RP_NO_FORCED_INLINE
#define RP_FN_HOT inline
#else
#define RP_FN_HOT inline __attribute__((always_inline))
#endif
#define RP_FN_COLD __attribute__((noinline)) inline
#define RP_OUT(T) T&
#define RP_INOUT(T) T&
#define RP_IN(T) const T&
#define RP_TABLE_BEGIN(name, n) inline const real name[n] = {
#define RP_TABLE_END                                                                               \
    }                                                                                              \
    ;

#define RP_CORE_PRELUDE                                                                            \
    using std::abs;                                                                                \
    using std::acos;                                                                               \
    using std::asin;                                                                               \
    using std::cos;                                                                                \
    using std::exp;                                                                                \
    using std::isnan;                                                                              \
    using std::log;                                                                                \
    using std::pow;                                                                                \
    using std::sin;                                                                                \
    using std::sqrt;                                                                               \
    using glm::clamp;                                                                              \
    using glm::cross;                                                                              \
    using glm::dot;                                                                                \
    using glm::length;                                                                             \
    using glm::max;                                                                                \
    using glm::min;                                                                                \
    using glm::mix;                                                                                \
    using glm::normalize;                                                                          \
    inline real rp_erf(real x) {                                                                   \
        return std::erf(x);                                                                        \
    }                                                                                              \
    inline real rp_erfc(real x) {                                                                  \
        return std::erfc(x);                                                                       \
    }                                                                                              \
    inline real rp_fdr_external(real eta) {                                                        \
        return real(::retroprism::fdr_external(double(eta)));                                      \
    }                                                                                              \
    /* The exact tier's Lambda: the rational fit in float, erfc in double (prism_core.inc). */     \
    const bool RP_LAMBDA_RATIONAL = sizeof(real) < sizeof(double);

namespace retroprism {

// Exact outside hemispherical reflectance of the top surface (prismatic_retroreflector.cpp);
// the C++ prelude's rp_fdr_external.
double fdr_external(double eta);

// Newton steps on std::erf after Giles' approximation: float reaches its rounding after one,
// double after two (each step squares the relative error of ~4e-7).
#define RP_ERFINV_REFINED(STEPS)                                                                   \
    inline real rp_erfinv(real y) {                                                                \
        real x = rp_erfinv_giles(y);                                                               \
        for (int i = 0; i < STEPS; ++i) {                                                          \
            real err = std::erf(x) - y;                                                            \
            x -= err / (real(1.1283791670955126) * std::exp(-x * x));                              \
        }                                                                                          \
        return x;                                                                                  \
    }

namespace f32 {
using real = float;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
RP_CORE_PRELUDE
#include "prism_special.inc"
RP_ERFINV_REFINED(1)
#ifdef RP_BOOTSTRAP_TABLES
#include "prism_tables_bootstrap.inc"
#else
#include "generated/prism_tables.inc"
#endif
#include "prism_core.inc"
} // namespace f32

namespace f64 {
using real = double;
using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
using vec4 = glm::dvec4;
RP_CORE_PRELUDE
#include "prism_special.inc"
RP_ERFINV_REFINED(2)
#ifdef RP_BOOTSTRAP_TABLES
#include "prism_tables_bootstrap.inc"
#else
#include "generated/prism_tables.inc"
#endif
#include "prism_core.inc"
} // namespace f64

// The core of a given precision as one type: core<float> forwards to f32, core<double> to f64.
template <class Real>
struct core;
// The core functions of namespace NS (f32, f64 or a generated variant's) as static members of
// a struct: the body of a type that stands for that core.
#define RP_CORE_MEMBERS(NS)                                                                        \
    using vec2 = NS::vec2;                                                                         \
    using vec3 = NS::vec3;                                                                         \
    using material = NS::rp_material;                                                              \
    using lobes = NS::rp_lobes;                                                                    \
    using incident = NS::rp_incident;                                                              \
    static bool eval(const material& m, vec3 wi, vec3 wo, lobes& r, real& pdf) {                   \
        return NS::rp_eval(m, wi, wo, r, pdf);                                                     \
    }                                                                                              \
    static bool eval_f(const material& m, vec3 wi, vec3 wo, lobes& r) {                            \
        return NS::rp_eval_f(m, wi, wo, r);                                                        \
    }                                                                                              \
    static bool sample(const material& m, vec3 wi, vec3 u, vec3& wo, lobes& r, real& pdf,          \
                       int& lobe) {                                                                \
        return NS::rp_sample(m, wi, u, wo, r, pdf, lobe);                                          \
    }                                                                                              \
    static bool sample_incident(const material& m, const incident& s, vec3 wi, vec3 u, vec3& wo,   \
                                lobes& r, real& pdf, int& lobe) {                                  \
        return NS::rp_sample_incident(m, s, wi, u, wo, r, pdf, lobe);                              \
    }                                                                                              \
    static void eval_lobes_pdf(const material& m, const incident& s, vec3 wi, vec3 wo, lobes& r,   \
                               real& pdf) {                                                        \
        NS::rp_eval_lobes_pdf(m, s, wi, wo, true, r, pdf);                                         \
    }                                                                                              \
    static bool reflects(const material& m, vec3 wi) {                                             \
        return NS::rp_incident_reflects(m, wi);                                                    \
    }                                                                                              \
    static void setup(const material& m, vec3 wi, incident& s) {                                   \
        NS::rp_incident_setup(m, wi, s);                                                           \
    }                                                                                              \
    static void incident_lobes(const material& m, vec3 wi, incident& s) {                          \
        NS::rp_incident_lobes(m, wi, s);                                                           \
    }                                                                                              \
    static void eval_lobes(const material& m, const incident& s, vec3 wi, vec3 wo, lobes& r) {     \
        NS::rp_eval_lobes(m, s, wi, wo, r);                                                        \
    }                                                                                              \
    static vec3 lobe_sample(const material& m, const incident& s, vec3 wi, int lobe, real u1,      \
                            real u2, real u3) {                                                    \
        return NS::rp_lobe_sample(m, s, wi, lobe, u1, u2, u3);                                     \
    }                                                                                              \
    static real lobe_pdf(const material& m, const incident& s, vec3 wi, vec3 wo, int lobe) {       \
        return NS::rp_lobe_pdf(m, s, wi, wo, lobe);                                                \
    }                                                                                              \
    static bool to_local(vec3 n, vec3 t, vec3 b, vec3 w, vec3& local) {                            \
        return NS::rp_to_local(n, t, b, w, local);                                                 \
    }

#define RP_CORE_DISPATCH(REAL, NS)                                                                 \
    template <>                                                                                    \
    struct core<REAL> {                                                                            \
        using real = REAL;                                                                         \
        RP_CORE_MEMBERS(NS)                                                                        \
    };
RP_CORE_DISPATCH(float, f32)
RP_CORE_DISPATCH(double, f64)
#undef RP_CORE_DISPATCH

} // namespace retroprism

// RP_CORE_PRELUDE and RP_ERFINV_REFINED stay defined: bench/variants.h instantiates generated
// C++ variants of the core with them.
