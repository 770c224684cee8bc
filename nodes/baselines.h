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

namespace retroprism::baselines {

// Below-the-horizon guard, the node's RP_MIN_COS.
constexpr double kMinCos = 1e-9;
constexpr double kPi = 3.14159265358979323846;

// Exact unpolarised reflectance of a dielectric interface for light arriving from the outside
// at cos(theta) = c, relative index eta; total internal reflection (eta < 1) returns 1.
// Lagarde, "Memo on Fresnel equations" (2013); MaterialX mx_fresnel_dielectric.
template <class Real>
inline Real fresnel_dielectric(Real c, Real eta) {
    if (c < Real(0)) return Real(1);
    const Real g2 = eta * eta + c * c - Real(1);
    if (g2 < Real(0)) return Real(1);
    const Real g = std::sqrt(g2);
    const Real x = (g - c) / (g + c);
    const Real y = ((g + c) * c - Real(1)) / ((g - c) * c + Real(1));
    return Real(0.5) * x * x * (Real(1) + y * y);
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
// MaterialX's GGX helpers (libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl, 1.39),
// templated on the real type, isotropic roughness. M_FLOAT_EPS is MaterialX's clamp constant.
namespace mx {

constexpr double M_FLOAT_EPS = 1e-8;

// GGX NDF; Burley 2012, Appendix B.2, Eq. 13 (mx_ggx_NDF), isotropic.
template <class Real>
inline Real ggx_ndf(const glm::vec<3, Real>& h, Real alpha) {
    const Real denom = (h.x * h.x + h.y * h.y) / (alpha * alpha) + h.z * h.z;
    return Real(1) / (Real(kPi) * alpha * alpha * denom * denom);
}

// Height-correlated Smith G2 of GGX; Heitz 2014, Eqs. 72 and 99 (mx_ggx_smith_G2).
template <class Real>
inline Real ggx_smith_g2(Real NdotL, Real NdotV, Real alpha) {
    const Real a2 = alpha * alpha;
    const Real lambdaL = std::sqrt(a2 + (Real(1) - a2) * NdotL * NdotL);
    const Real lambdaV = std::sqrt(a2 + (Real(1) - a2) * NdotV * NdotV);
    return Real(2) / (lambdaL / NdotL + lambdaV / NdotV);
}

// GGX directional albedo: MaterialX's rational quadratic fit (mx_ggx_dir_albedo_analytic, the
// default DIRECTIONAL_ALBEDO_METHOD 0), returned as the scale A and bias B of F0 and F90.
template <class Real>
inline void ggx_dir_albedo_ab(Real NdotV, Real alpha, Real& A, Real& B) {
    const Real x = NdotV, y = alpha, x2 = x * x, y2 = y * y;
    // Columns r.x, r.y, r.z, r.w of the fit's 9 monomials 1, x, y, xy, x2, y2, x2y, xy2, x2y2.
    static const Real c[9][4] = {{Real(0.10031), Real(0.93450), Real(1.0), Real(1.0)},
                                 {Real(-0.63301), Real(-2.32352), Real(-1.76427), Real(0.22797)},
                                 {Real(9.74995), Real(2.22823), Real(8.26501), Real(15.93688)},
                                 {Real(-2.02075), Real(-3.74584), Real(11.54840), Real(-55.82466)},
                                 {Real(29.38247), Real(1.42450), Real(28.99991), Real(13.07919)},
                                 {Real(-8.24713), Real(-0.76829), Real(-7.50867), Real(41.25882)},
                                 {Real(-26.51510), Real(1.43366), Real(-36.16186), Real(54.86775)},
                                 {Real(19.98406), Real(0.29060), Real(15.85408), Real(300.10923)},
                                 {Real(-5.41717), Real(0.62933), Real(33.41550), Real(-284.73288)}};
    const Real m[9] = {Real(1), x, y, x * y, x2, y2, x2 * y, x * y2, x2 * y2};
    Real r[4] = {0, 0, 0, 0};
    for (int k = 0; k < 9; ++k)
        for (int j = 0; j < 4; ++j)
            r[j] += c[k][j] * m[k];
    A = r[0] / r[2];
    B = r[1] / r[3];
}

template <class Real>
inline Real ggx_dir_albedo(Real NdotV, Real alpha, Real F0, Real F90) {
    Real A, B;
    ggx_dir_albedo_ab(NdotV, alpha, A, B);
    return F0 * A + F90 * B;
}

// Turquin 2019, Eqs. 14 and 16 (mx_ggx_energy_compensation).
template <class Real>
inline Real ggx_energy_compensation(Real NdotV, Real alpha, Real Fss) {
    const Real Ess = ggx_dir_albedo(NdotV, alpha, Real(1), Real(1));
    return Real(1) + Fss * (Real(1) - Ess) / Ess;
}

template <class Real>
inline Real ior_to_f0(Real ior) {
    const Real r = (ior - Real(1)) / (ior + Real(1));
    return r * r;
}

} // namespace mx

// ---------------------------------------------------------------------------------------------
// The MaterialX-style "Minimal Retroreflective Microfacet" (MRM) baseline: Portsmouth, Raab,
// Belcour, Liu, JCGT 15(1) 2026, as MaterialX's dielectric_bsdf evaluates it with
// retroreflective = true: the GGX reflection BRDF with the view vector replaced by
// V' = reflect(-V, N) = (-V.x, -V.y, V.z) in the local frame, every quantity derived from V
// (half vector, Fresnel, energy compensation) taken from V'. In a standard_surface-like set-up
// it is the top of a `layer` over a Lambertian base (oren_nayar_diffuse_bsdf, roughness 0),
// and the layer passes the base's response times the top's throughput:
//
//   f = specular * tint * D(h') F(V'.h') G2(L, V') comp / (4 cos_i cos_o)
//     + (1 - specular * E(cos_o) * comp) * color / pi,
//   h' = normalize(L + V'),  F = exact dielectric Fresnel (mx_fresnel_dielectric),
//   comp = 1 + F (1 - E1) / E1 (energy compensation, E1 = mx_ggx_dir_albedo(cos_o, a, 1, 1)),
//   E(cos_o) = mx_ggx_dir_albedo(cos_o, a, F0, 1), F0 = ((ior - 1) / (ior + 1))^2,
//
// with MaterialX's clamps: cosines and V'.h' to [1e-8, 1], roughness a to [1e-8, 1]. MaterialX
// evaluates response = f cos_i; here both directions below the horizon give 0 instead.
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

    // The two lobes with `specular` = 1 and `color` = 1 factored out: f = specular * s * tint
    // + color * d * (1 - specular * e). For the fitter (linear in specular and color).
    struct Unit {
        Real s = 0; // GGX retro lobe, unit weight and tint
        Real d = 0; // Lambert base with unit colour: 1 / pi
        Real e = 0; // directional albedo E(cos_o) * comp of the layer's throughput
    };

    Unit unit(const vec3& wi, const vec3& wo) const {
        Unit u;
        if (!(wi.z > Real(kMinCos)) || !(wo.z > Real(kMinCos))) return u;
        const Real eps = Real(mx::M_FLOAT_EPS);
        const vec3 V(-wo.x, -wo.y, wo.z); // reflect(-V, N)
        const Real NdotL = std::clamp(wi.z, eps, Real(1));
        const Real NdotV = std::clamp(V.z, eps, Real(1));
        const Real alpha = std::clamp(roughness, eps, Real(1));
        const vec3 H = glm::normalize(wi + V);
        const Real VdotH = std::clamp(glm::dot(V, H), eps, Real(1));
        const Real F = fresnel_dielectric(VdotH, ior);
        const Real D = mx::ggx_ndf(H, alpha);
        const Real G = mx::ggx_smith_g2(NdotL, NdotV, alpha);
        const Real comp = mx::ggx_energy_compensation(NdotV, alpha, F);
        u.s = D * F * G * comp / (Real(4) * NdotV * NdotL);
        u.d = Real(1.0 / kPi);
        u.e = mx::ggx_dir_albedo(NdotV, alpha, mx::ior_to_f0(ior), Real(1)) * comp;
        return u;
    }

    Parts parts(const vec3& wi, const vec3& wo) const {
        const Unit u = unit(wi, wo);
        Parts p;
        p.specular = tint * (specular * u.s);
        p.diffuse = color * (u.d * (Real(1) - specular * u.e));
        return p;
    }

    vec3 f(const vec3& wi, const vec3& wo) const { return parts(wi, wo).total(); }
};
using RetroreflectiveGGX = RetroreflectiveGGXT<double>;

} // namespace retroprism::baselines
