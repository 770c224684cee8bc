// baselines.h: comparison BRDFs for the prismatic retroreflector node: the MaterialX-style
// "Minimal Retroreflective Microfacet" model, a Lambertian and a Beckmann Cook-Torrance.
//
// Conventions (the node's, nodes/prismatic_retroreflector.h): local frame, normal +z; wi points
// toward the light and wo toward the viewer, both unit vectors away from the surface;
// f(wi, wo) is the BRDF in 1/sr WITHOUT the cosine factor, per RGB channel. Directions with
// cos(theta) <= kMinCos (either one) give exactly 0: these are reflection-only BRDFs.
// Each model is a small value type: public parameters and a const `f(wi, wo)`, templated on the
// real type (float for the benchmarks' like-for-like timing, double elsewhere: the plain names
// Lambert, BeckmannCookTorrance and RetroreflectiveGGX are the double models).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "prism_core.h"

// The baseline's math core in the node core's float and double namespaces, after the node's
// core (prism_core.h), whose guards, Fresnel factor and frame it uses.
namespace retroprism::f32 {
#include "mrm_core.inc"
} // namespace retroprism::f32
namespace retroprism::f64 {
#include "mrm_core.inc"
} // namespace retroprism::f64

namespace retroprism::baselines {

// Below-the-horizon guard: the node's RP_MIN_COS.
inline const double kMinCos = f64::RP_MIN_COS;
constexpr double kPi = 3.14159265358979323846;

// The node core's exact dielectric Fresnel factor (prism_core.inc) of the real type.
inline float fresnel_dielectric(float c, float eta) {
    return f32::rp_fresnel_dielectric(c, eta);
}
inline double fresnel_dielectric(double c, double eta) {
    return f64::rp_fresnel_dielectric(c, eta);
}

// ---------------------------------------------------------------------------------------------
// Lambert: f = color / pi.
template <class Real>
struct LambertT {
    using vec3 = glm::vec<3, Real>;
    vec3 color{Real(0.8)};

    vec3 f(const vec3& wi, const vec3& wo) const {
        if (!(wi.z > Real(kMinCos)) || !(wo.z > Real(kMinCos))) return vec3(Real(0));
        return color * Real(1.0 / kPi);
    }
};
using Lambert = LambertT<double>;

// ---------------------------------------------------------------------------------------------
// Beckmann Cook-Torrance: a rough dielectric interface, reflection only.
// f = tint F(wi.h, eta) D(h) G2(wi, wo) / (4 cos_i cos_o), h = normalize(wi + wo), with the
// Beckmann NDF, the height-correlated Smith G2 of the Beckmann Lambda (Heitz 2014, Eq. 99 and
// Eq. 72 with the exact erf) and the exact dielectric Fresnel factor (MODEL.md section 1).
template <class Real>
struct BeckmannCookTorranceT {
    using vec3 = glm::vec<3, Real>;
    Real roughness = Real(0.1); // Beckmann alpha, floored at 1e-4
    Real ior = Real(1.5);
    vec3 tint{Real(1)};

    // Beckmann Smith Lambda at tan^2(theta); 0 at normal incidence.
    static Real lambda(Real tan2Theta, Real alpha) {
        if (!(tan2Theta > Real(0))) return Real(0);
        const Real a = Real(1) / (alpha * std::sqrt(tan2Theta));
        return Real(0.5) * (-std::erfc(a)) +
               std::exp(-a * a) / (Real(2) * a * Real(std::sqrt(kPi)));
    }

    vec3 f(const vec3& wi, const vec3& wo) const {
        const Real cosI = wi.z, cosO = wo.z;
        if (!(cosI > Real(kMinCos)) || !(cosO > Real(kMinCos))) return vec3(Real(0));
        const Real alpha = std::max(roughness, Real(1e-4));
        const vec3 h = glm::normalize(wi + wo);
        if (!(h.z > Real(kMinCos))) return vec3(Real(0));
        const Real cos2M = h.z * h.z, tan2M = (Real(1) - cos2M) / cos2M;
        const Real e = tan2M / (alpha * alpha);
        if (e > Real(80)) return vec3(Real(0));
        const Real D = std::exp(-e) / (Real(kPi) * alpha * alpha * cos2M * cos2M);
        const Real G2 =
            Real(1) / (Real(1) + lambda((Real(1) - cosI * cosI) / (cosI * cosI), alpha) +
                       lambda((Real(1) - cosO * cosO) / (cosO * cosO), alpha));
        const Real F = fresnel_dielectric(glm::dot(wi, h), ior);
        return tint * (F * D * G2 / (Real(4) * cosI * cosO));
    }
};
using BeckmannCookTorrance = BeckmannCookTorranceT<double>;

// ---------------------------------------------------------------------------------------------
// The MaterialX-style "Minimal Retroreflective Microfacet" (MRM) baseline: Portsmouth, Raab,
// Belcour, Liu, JCGT 15(1) 2026, as MaterialX's dielectric_bsdf evaluates it with
// retroreflective = true, the top of a `layer` over a Lambertian base (oren_nayar_diffuse_bsdf,
// roughness 0). Its math, the formula and MaterialX's clamps, is nodes/mrm_core.inc (written once
// for C++ and GLSL; the look-dev page renders its GLSL form): the value type below holds the
// parameters and calls it in the real type's core.
template <class Real>
struct MrmCore;
#define RP_MRM_DISPATCH(REAL, NS)                                                                  \
    template <>                                                                                    \
    struct MrmCore<REAL> {                                                                         \
        using vec3 = NS::vec3;                                                                     \
        static void unit(REAL roughness, REAL ior, vec3 wi, vec3 wo, REAL& s, REAL& d, REAL& e) {  \
            NS::rp_mrm_unit(roughness, ior, wi, wo, s, d, e);                                      \
        }                                                                                          \
        static void lobes(REAL roughness, REAL ior, REAL specular, vec3 tint, vec3 color, vec3 wi, \
                          vec3 wo, vec3& specularLobe, vec3& diffuseLobe) {                        \
            NS::rp_mrm_lobes(roughness, ior, specular, tint, color, wi, wo, specularLobe,          \
                             diffuseLobe);                                                         \
        }                                                                                          \
    };
RP_MRM_DISPATCH(float, f32)
RP_MRM_DISPATCH(double, f64)
#undef RP_MRM_DISPATCH

template <class Real>
struct RetroreflectiveGGXT {
    using vec3 = glm::vec<3, Real>;
    Real roughness = Real(0.1); // GGX alpha (dielectric_bsdf's roughness input, isotropic)
    Real ior = Real(1.5);
    Real specular = Real(1); // the dielectric_bsdf's weight
    vec3 tint{Real(1)};      // the dielectric_bsdf's tint
    vec3 color{Real(0.8)};   // the Lambertian base under the layer

    struct Parts {
        vec3 specular{Real(0)}; // the retroreflective GGX lobe, weight and tint applied
        vec3 diffuse{Real(0)};  // the base, attenuated by the layer's throughput
        vec3 total() const { return specular + diffuse; }
    };

    // The two lobes with `specular` = 1 and `color` = 1 factored out:
    // f = specular * s * tint + color * d * (1 - specular * e). For the fitter (linear in
    // specular and color).
    struct Unit {
        Real s = 0; // GGX retro lobe, unit weight and tint
        Real d = 0; // Lambert base with unit colour: 1 / pi
        Real e = 0; // directional albedo E(cos_o) * comp of the layer's throughput
    };

    Unit unit(const vec3& wi, const vec3& wo) const {
        Unit u;
        MrmCore<Real>::unit(roughness, ior, wi, wo, u.s, u.d, u.e);
        return u;
    }

    Parts parts(const vec3& wi, const vec3& wo) const {
        Parts p;
        MrmCore<Real>::lobes(roughness, ior, specular, tint, color, wi, wo, p.specular, p.diffuse);
        return p;
    }

    vec3 f(const vec3& wi, const vec3& wo) const { return parts(wi, wo).total(); }
};
using RetroreflectiveGGX = RetroreflectiveGGXT<double>;

} // namespace retroprism::baselines
