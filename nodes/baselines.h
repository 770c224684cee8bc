// baselines.h: comparison BRDFs for the prismatic retroreflector node: the MaterialX-style
// "Minimal Retroreflective Microfacet" model, a Lambertian and a Beckmann Cook-Torrance.
//
// Conventions (the node's, nodes/prismatic_retroreflector.h): local frame, normal +z; wi points
// toward the light and wo toward the viewer, both unit vectors away from the surface;
// f(wi, wo) is the BRDF in 1/sr WITHOUT the cosine factor, per RGB channel. Directions with
// cos(theta) <= kMinCos (either one) give exactly 0: these are reflection-only BRDFs.
// Each model is a small value type: public parameters and a const `f(wi, wo)`.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace retroprism::baselines {

using dvec3 = glm::dvec3;

// Below-the-horizon guard, the node's RP_MIN_COS.
constexpr double kMinCos = 1e-9;
constexpr double kPi = 3.14159265358979323846;

// Exact unpolarised reflectance of a dielectric interface for light arriving from the outside
// at cos(theta) = c, relative index eta; total internal reflection (eta < 1) returns 1.
// Lagarde, "Memo on Fresnel equations" (2013); MaterialX mx_fresnel_dielectric.
inline double fresnel_dielectric(double c, double eta) {
    if (c < 0.0) return 1.0;
    const double g2 = eta * eta + c * c - 1.0;
    if (g2 < 0.0) return 1.0;
    const double g = std::sqrt(g2);
    const double x = (g - c) / (g + c);
    const double y = ((g + c) * c - 1.0) / ((g - c) * c + 1.0);
    return 0.5 * x * x * (1.0 + y * y);
}

// ---------------------------------------------------------------------------------------------
// Lambert: f = color / pi.
struct Lambert {
    dvec3 color{0.8};

    dvec3 f(const dvec3& wi, const dvec3& wo) const {
        if (!(wi.z > kMinCos) || !(wo.z > kMinCos)) return dvec3(0.0);
        return color / kPi;
    }
};

// ---------------------------------------------------------------------------------------------
// Beckmann Cook-Torrance: a rough dielectric interface, reflection only.
// f = tint F(wi.h, eta) D(h) G2(wi, wo) / (4 cos_i cos_o), h = normalize(wi + wo), with the
// Beckmann NDF, the height-correlated Smith G2 of the Beckmann Lambda (Heitz 2014, Eq. 99 and
// Eq. 72 with the exact erf) and the exact dielectric Fresnel factor (MODEL.md section 1).
struct BeckmannCookTorrance {
    double roughness = 0.1; // Beckmann alpha, floored at 1e-4
    double ior = 1.5;
    dvec3 tint{1.0};

    // Beckmann Smith Lambda at tan^2(theta); 0 at normal incidence.
    static double lambda(double tan2Theta, double alpha) {
        if (!(tan2Theta > 0.0)) return 0.0;
        const double a = 1.0 / (alpha * std::sqrt(tan2Theta));
        return 0.5 * (-std::erfc(a)) + std::exp(-a * a) / (2.0 * a * std::sqrt(kPi));
    }

    dvec3 f(const dvec3& wi, const dvec3& wo) const {
        const double cosI = wi.z, cosO = wo.z;
        if (!(cosI > kMinCos) || !(cosO > kMinCos)) return dvec3(0.0);
        const double alpha = std::max(roughness, 1e-4);
        const dvec3 h = glm::normalize(wi + wo);
        if (!(h.z > kMinCos)) return dvec3(0.0);
        const double cos2M = h.z * h.z, tan2M = (1.0 - cos2M) / cos2M;
        const double e = tan2M / (alpha * alpha);
        if (e > 80.0) return dvec3(0.0);
        const double D = std::exp(-e) / (kPi * alpha * alpha * cos2M * cos2M);
        const double G2 = 1.0 / (1.0 + lambda((1.0 - cosI * cosI) / (cosI * cosI), alpha) +
                                 lambda((1.0 - cosO * cosO) / (cosO * cosO), alpha));
        const double F = fresnel_dielectric(glm::dot(wi, h), ior);
        return tint * (F * D * G2 / (4.0 * cosI * cosO));
    }
};

// ---------------------------------------------------------------------------------------------
// MaterialX's GGX helpers (libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl, 1.39),
// in double precision, isotropic roughness. M_FLOAT_EPS is MaterialX's clamp constant.
namespace mx {

constexpr double M_FLOAT_EPS = 1e-8;

// GGX NDF; Burley 2012, Appendix B.2, Eq. 13 (mx_ggx_NDF), isotropic.
inline double ggx_ndf(const dvec3& h, double alpha) {
    const double denom = (h.x * h.x + h.y * h.y) / (alpha * alpha) + h.z * h.z;
    return 1.0 / (kPi * alpha * alpha * denom * denom);
}

// Height-correlated Smith G2 of GGX; Heitz 2014, Eqs. 72 and 99 (mx_ggx_smith_G2).
inline double ggx_smith_g2(double NdotL, double NdotV, double alpha) {
    const double a2 = alpha * alpha;
    const double lambdaL = std::sqrt(a2 + (1.0 - a2) * NdotL * NdotL);
    const double lambdaV = std::sqrt(a2 + (1.0 - a2) * NdotV * NdotV);
    return 2.0 / (lambdaL / NdotL + lambdaV / NdotV);
}

// GGX directional albedo: MaterialX's rational quadratic fit (mx_ggx_dir_albedo_analytic, the
// default DIRECTIONAL_ALBEDO_METHOD 0), returned as the scale A and bias B of F0 and F90.
inline void ggx_dir_albedo_ab(double NdotV, double alpha, double& A, double& B) {
    const double x = NdotV, y = alpha, x2 = x * x, y2 = y * y;
    // Columns r.x, r.y, r.z, r.w of the fit's 9 monomials 1, x, y, xy, x2, y2, x2y, xy2, x2y2.
    static const double c[9][4] = {{0.10031, 0.93450, 1.0, 1.0},
                                   {-0.63301, -2.32352, -1.76427, 0.22797},
                                   {9.74995, 2.22823, 8.26501, 15.93688},
                                   {-2.02075, -3.74584, 11.54840, -55.82466},
                                   {29.38247, 1.42450, 28.99991, 13.07919},
                                   {-8.24713, -0.76829, -7.50867, 41.25882},
                                   {-26.51510, 1.43366, -36.16186, 54.86775},
                                   {19.98406, 0.29060, 15.85408, 300.10923},
                                   {-5.41717, 0.62933, 33.41550, -284.73288}};
    const double m[9] = {1.0, x, y, x * y, x2, y2, x2 * y, x * y2, x2 * y2};
    double r[4] = {0, 0, 0, 0};
    for (int k = 0; k < 9; ++k)
        for (int j = 0; j < 4; ++j)
            r[j] += c[k][j] * m[k];
    A = r[0] / r[2];
    B = r[1] / r[3];
}

inline double ggx_dir_albedo(double NdotV, double alpha, double F0, double F90) {
    double A, B;
    ggx_dir_albedo_ab(NdotV, alpha, A, B);
    return F0 * A + F90 * B;
}

// Turquin 2019, Eqs. 14 and 16 (mx_ggx_energy_compensation).
inline double ggx_energy_compensation(double NdotV, double alpha, double Fss) {
    const double Ess = ggx_dir_albedo(NdotV, alpha, 1.0, 1.0);
    return 1.0 + Fss * (1.0 - Ess) / Ess;
}

inline double ior_to_f0(double ior) {
    const double r = (ior - 1.0) / (ior + 1.0);
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
struct RetroreflectiveGGX {
    double roughness = 0.1; // GGX alpha (dielectric_bsdf's roughness input, isotropic)
    double ior = 1.5;
    double specular = 1.0; // the dielectric_bsdf's weight
    dvec3 tint{1.0};       // the dielectric_bsdf's tint
    dvec3 color{0.8};      // the Lambertian base under the layer

    struct Parts {
        dvec3 specular{0.0}; // the retroreflective GGX lobe, weight and tint applied
        dvec3 diffuse{0.0};  // the base, attenuated by the layer's throughput
        dvec3 total() const { return specular + diffuse; }
    };

    // The two lobes with `specular` = 1 and `color` = 1 factored out: f = specular * s * tint
    // + color * d * (1 - specular * e). For the fitter (linear in specular and color).
    struct Unit {
        double s = 0; // GGX retro lobe, unit weight and tint
        double d = 0; // Lambert base with unit colour: 1 / pi
        double e = 0; // directional albedo E(cos_o) * comp of the layer's throughput
    };

    Unit unit(const dvec3& wi, const dvec3& wo) const {
        Unit u;
        if (!(wi.z > kMinCos) || !(wo.z > kMinCos)) return u;
        using namespace mx;
        const dvec3 V(-wo.x, -wo.y, wo.z); // reflect(-V, N)
        const double NdotL = std::clamp(wi.z, M_FLOAT_EPS, 1.0);
        const double NdotV = std::clamp(V.z, M_FLOAT_EPS, 1.0);
        const double alpha = std::clamp(roughness, M_FLOAT_EPS, 1.0);
        const dvec3 H = glm::normalize(wi + V);
        const double VdotH = std::clamp(glm::dot(V, H), M_FLOAT_EPS, 1.0);
        const double F = fresnel_dielectric(VdotH, ior);
        const double D = ggx_ndf(H, alpha);
        const double G = ggx_smith_g2(NdotL, NdotV, alpha);
        const double comp = ggx_energy_compensation(NdotV, alpha, F);
        u.s = D * F * G * comp / (4.0 * NdotV * NdotL);
        u.d = 1.0 / kPi;
        u.e = ggx_dir_albedo(NdotV, alpha, ior_to_f0(ior), 1.0) * comp;
        return u;
    }

    Parts parts(const dvec3& wi, const dvec3& wo) const {
        const Unit u = unit(wi, wo);
        Parts p;
        p.specular = tint * (specular * u.s);
        p.diffuse = color * (u.d * (1.0 - specular * u.e));
        return p;
    }

    dvec3 f(const dvec3& wi, const dvec3& wo) const { return parts(wi, wo).total(); }
};

} // namespace retroprism::baselines
