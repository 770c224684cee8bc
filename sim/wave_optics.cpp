// wave_optics.cpp: the physical-optics ground truth (see wave_optics.h, docs/wave_optics.md).
#include "wave_optics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "error.h"

namespace retroprism {
namespace sim {
namespace wave {

namespace {

const cplx kI(0.0, 1.0);

double cross2(const dvec2& a, const dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

// sin(x) / x, by its series where the quotient loses digits.
double sinc(double x) {
    return std::abs(x) < 1e-4 ? 1.0 - x * x / 6.0 : std::sin(x) / x;
}

cplx dot(const Field& e, const dvec3& v) {
    return e[0] * v.x + e[1] * v.y + e[2] * v.z;
}

Field field_of(const dvec3& v, cplx a) {
    return {a * v.x, a * v.y, a * v.z};
}

Field add(const Field& a, const Field& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

void require(bool ok, const std::string& what, double v, const std::string& range) {
    if (!ok) throw InputError(what + " " + num(v) + ": expected " + range);
}

} // namespace

// ---- Polygons ----------------------------------------------------------------------------

double polygon_area(const Polygon& p) {
    double a = 0;
    for (size_t j = 0; j < p.size(); ++j)
        a += cross2(p[j], p[(j + 1) % p.size()]);
    return 0.5 * a;
}

double polygon_perimeter(const Polygon& p) {
    double l = 0;
    for (size_t j = 0; j < p.size(); ++j)
        l += glm::length(p[(j + 1) % p.size()] - p[j]);
    return l;
}

dvec2 polygon_centroid(const Polygon& p) {
    if (p.empty()) return dvec2(0.0);
    dvec2 c(0.0);
    double a = 0;
    for (size_t j = 0; j < p.size(); ++j) {
        const dvec2 &u = p[j], &v = p[(j + 1) % p.size()];
        const double w = cross2(u, v);
        a += w;
        c += w * (u + v);
    }
    if (std::abs(a) < 1e-300) return p[0];
    return c / (3.0 * a);
}

Polygon clip_polygon(const Polygon& p, const std::vector<double>& f) {
    Polygon out;
    const size_t n = p.size();
    for (size_t j = 0; j < n; ++j) {
        const size_t k = (j + 1) % n;
        const bool inJ = f[j] >= 0, inK = f[k] >= 0;
        if (inJ) out.push_back(p[j]);
        if (inJ != inK) {
            const double t = f[j] / (f[j] - f[k]);
            out.push_back(p[j] + t * (p[k] - p[j]));
        }
    }
    return out;
}

PolygonTransform::PolygonTransform(const Polygon& p) {
    area = polygon_area(p);
    centroid = polygon_centroid(p);
    for (const dvec2& v : p) {
        about.push_back(v - centroid);
        radius = std::max(radius, glm::length(v - centroid));
    }
}

namespace {

// The transform of the triangle (0, a, b) over twice its signed area, phi(alpha, beta) =
// integral over the unit simplex of exp(-i (alpha u + beta v)) du dv, by its power series:
// the integral of (alpha u + beta v)^n is n! h_n / (n + 2)! (h_n = sum_j alpha^j beta^(n-j),
// the complete homogeneous polynomial), so phi = sum_n (-i)^n h_n / (n + 2)!. For |alpha|,
// |beta| <= 1 the 22nd term is below 1e-20.
cplx simplex_series(double alpha, double beta) {
    cplx sum = 0.0, power = 1.0; // (-i)^n
    double h = 1.0, betaN = 1.0, factorial = 2.0;
    for (int n = 0; n < 22; ++n) {
        if (n > 0) {
            betaN *= beta;
            h = betaN + alpha * h;
            power *= -kI;
            factorial *= double(n + 2);
        }
        sum += power * (h / factorial);
    }
    return sum;
}

} // namespace

cplx PolygonTransform::operator()(const dvec2& k) const {
    const size_t n = about.size();
    if (n < 3) return 0.0;
    const double k2 = glm::dot(k, k);
    cplx sum = 0.0;
    if (k2 * radius * radius < 1.0) {
        for (size_t j = 0; j < n; ++j) {
            const dvec2 &a = about[j], &b = about[(j + 1) % n];
            sum += cross2(a, b) * simplex_series(glm::dot(k, a), glm::dot(k, b));
        }
    } else {
        for (size_t j = 0; j < n; ++j) {
            const dvec2 &a = about[j], &b = about[(j + 1) % n];
            const dvec2 edge = b - a;
            // (k.n) L with n the outward normal of a counter-clockwise polygon: (D.y, -D.x) / L.
            const double kn = k.x * edge.y - k.y * edge.x;
            const double km = glm::dot(k, 0.5 * (a + b));
            sum += kn * sinc(0.5 * glm::dot(k, edge)) * cplx(std::cos(km), -std::sin(km));
        }
        sum *= kI / k2;
    }
    const double kc = glm::dot(k, centroid);
    return sum * cplx(std::cos(kc), -std::sin(kc));
}

// ---- Fresnel ------------------------------------------------------------------------------

Fresnel fresnel(double cosThetaI, double n1, cplx n2) {
    const double ci = std::clamp(cosThetaI, 0.0, 1.0);
    const cplx ratio = n1 / n2;
    cplx ct = std::sqrt(1.0 - ratio * ratio * (1.0 - ci * ci));
    if ((n2 * ct).imag() < 0) ct = -ct;
    Fresnel f;
    f.cosT = ct;
    f.rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
    f.rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
    f.ts = 2.0 * n1 * ci / (n1 * ci + n2 * ct);
    f.tp = 2.0 * n1 * ci / (n2 * ci + n1 * ct);
    return f;
}

void sp_basis(const dvec3& k, const dvec3& n, dvec3& s, dvec3& p) {
    const dvec3 c = glm::cross(k, n);
    if (glm::length(c) > 1e-12) {
        s = glm::normalize(c);
    } else {
        const dvec3 a = std::abs(k.y) < 0.9 ? dvec3(0, 1, 0) : dvec3(1, 0, 0);
        s = glm::normalize(a - glm::dot(a, k) * k);
    }
    p = glm::cross(s, k);
}

Field reflect_field(const Field& e, dvec3& k, const dvec3& normal, double n1, Face face,
                    cplx metal) {
    const double ci = -glm::dot(k, normal);
    dvec3 s, p;
    sp_basis(k, normal, s, p);
    const dvec3 kr = k + 2.0 * ci * normal;
    const dvec3 pr = glm::cross(s, kr);
    cplx rs = -1.0, rp = 1.0;
    if (face != Face::kIdeal) {
        const Fresnel f = fresnel(ci, n1, face == Face::kTir ? cplx(1.0) : metal);
        rs = f.rs;
        rp = f.rp;
    }
    k = kr;
    return add(field_of(s, rs * dot(e, s)), field_of(pr, rp * dot(e, p)));
}

Field transmit_field(const Field& e, dvec3& k, const dvec3& normal, double n1, double n2) {
    const double ci = -glm::dot(k, normal);
    dvec3 s, p;
    sp_basis(k, normal, s, p);
    const Fresnel f = fresnel(ci, n1, n2);
    const double ct = f.cosT.real();
    const double r = n1 / n2;
    k = glm::normalize(r * (k + ci * normal) - ct * normal);
    const dvec3 pt = glm::cross(s, k);
    return add(field_of(s, f.ts * dot(e, s)), field_of(pt, f.tp * dot(e, p)));
}

namespace {

// Aluminium at 550 nm (Rakic 1995): the shape of metal_index's N.
const cplx kAluminium(0.958, 6.69);
constexpr double kMetalScaleMin = 3.0; // above the reflectance's minimum near a = 2.2

double metal_reflectance_at(double eta, cplx n2) {
    const Fresnel f = fresnel(1.0 / std::sqrt(3.0), eta, n2);
    return 0.5 * (std::norm(f.rs) + std::norm(f.rp));
}

} // namespace

cplx metal_index(double reflectance, double eta) {
    if (!(reflectance >= 0.0 && reflectance < 1.0))
        throw InputError("metal_reflectance " + num(reflectance) +
                         ": expected a number in [0, 1) (metallized prisms)");
    // Bisection on a monotone family: the aluminium-shaped scale a in [3, 1e7] where it reaches
    // the reflectance, else the absorbing dielectric eta + i kappa, kappa in [0, 1e7] (0 at
    // kappa = 0, up to the aluminium family's least at kappa ~ 5.9).
    const cplx shape = kAluminium / kAluminium.imag();
    const bool aluminium = reflectance >= metal_reflectance_at(eta, kMetalScaleMin * shape);
    auto index = [&](double x) { return aluminium ? x * shape : cplx(eta, x); };
    double a = aluminium ? kMetalScaleMin : 0.0, b = 1e7;
    for (int it = 0; it < 200 && b - a > 1e-12 * b; ++it) {
        const double mid = a > 0 ? std::sqrt(a * b) : 0.5 * (a + b);
        (metal_reflectance_at(eta, index(mid)) < reflectance ? a : b) = mid;
    }
    return index(0.5 * (a + b));
}

void check_material(const WaveMaterial& m) {
    require(m.ior >= 1.0 && m.ior <= 3.0, "ior", m.ior, "a number in [1, 3]");
    require(m.prism_reflection >= 0 && m.prism_reflection <= 2, "prism_reflection",
            m.prism_reflection, "0 (ideal), 1 (tir) or 2 (metallized)");
    if (m.prism_reflection == 2) metal_index(m.metal_reflectance, m.ior);
    require(std::abs(m.cant_deg) <= 30.0, "cant_deg", m.cant_deg, "a number in [-30, 30]");
    for (double e : m.dihedral_faces_arcmin) {
        require(std::abs(e) <= 60.0, "dihedral_faces_arcmin", e, "a number in [-60, 60]");
        if (e != 0.0 && m.dihedral_arcmin != 0.0)
            throw InputError("dihedral_faces_arcmin: expected 0 when dihedral_arcmin is set (" +
                             num(m.dihedral_arcmin) + ")");
    }
    require(std::abs(m.dihedral_arcmin) <= 60.0, "dihedral_arcmin", m.dihedral_arcmin,
            "a number in [-60, 60]");
    require(m.pitch_um >= 1.0 && m.pitch_um <= 1e5, "pitch_um", m.pitch_um, "a number in [1, 1e5]");
}

CubeCorner wave_corner(const WaveMaterial& m, double psi) {
    const std::array<double, 3>& e = m.dihedral_faces_arcmin;
    if (e[0] != 0.0 || e[1] != 0.0 || e[2] != 0.0) return cube_corner(m.cant_deg, e.data(), psi);
    return cube_corner(m.cant_deg, m.dihedral_arcmin, psi);
}

} // namespace wave
} // namespace sim
} // namespace retroprism
