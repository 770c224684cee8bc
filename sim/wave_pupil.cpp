// wave_pupil.cpp: the exit pupil of one cube corner, face order by face order, and its far field
// in closed form (see wave_optics.h, docs/wave_optics.md).
#include <algorithm>
#include <cmath>

#include "error.h"
#include "wave_optics.h"

namespace retroprism {
namespace sim {
namespace wave {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A ray of the order `faces` from the aperture point (p, 1) along d: its three face hits, its
// exit point on the aperture plane and its length, all affine in p (planar faces). Directions
// are checked once per order (order_directions), not here.
struct OrderRay {
    dvec3 hit[3];
    dvec3 exit;
    double length;
};

OrderRay trace_order(const CubeCorner& cc, const dvec3& d, const std::array<int, 3>& faces,
                     const dvec2& p) {
    OrderRay r;
    dvec3 x(p, 1.0), dir = d;
    r.length = 0;
    for (int step = 0; step < 3; ++step) {
        const dvec3& e = cc.e[faces[size_t(step)]];
        const double t = -glm::dot(x, e) / glm::dot(dir, e);
        x += t * dir;
        r.length += t;
        r.hit[step] = x;
        dir -= 2.0 * glm::dot(dir, e) * e;
    }
    const double t = (1.0 - x.z) / dir.z;
    r.exit = x + t * dir;
    r.length += t;
    return r;
}

// The directions after each reflection of the order, or false when the order cannot happen
// (a face met from behind, or no way up after the third).
bool order_directions(const CubeCorner& cc, const dvec3& d, const std::array<int, 3>& faces,
                      dvec3& last) {
    dvec3 dir = d;
    for (int step = 0; step < 3; ++step) {
        const dvec3& e = cc.e[faces[size_t(step)]];
        if (!(glm::dot(dir, e) < 0)) return false;
        dir -= 2.0 * glm::dot(dir, e) * e;
    }
    last = dir;
    return dir.z > 0;
}

// The constraints of the order on the entry point, each an affine function of it: every face
// hit inside the other faces' half-spaces and below the aperture plane, the exit point inside the
// aperture. Value c of the ray r.
constexpr int kConstraints = 3 * 3 + 3;
double constraint(const CubeCorner& cc, const std::array<int, 3>& faces, const OrderRay& r, int c) {
    if (c < 9) {
        const int step = c / 3, which = c % 3;
        if (which == faces[size_t(step)]) return 1.0 - r.hit[step].z; // below the aperture
        return glm::dot(r.hit[step], cc.e[which]);
    }
    return glm::dot(r.exit, cc.e[c - 9]);
}

// The aperture triangle's vertices (unit corner), counter-clockwise.
Polygon unit_aperture(const CubeCorner& cc) {
    Polygon t;
    for (int k = 0; k < 3; ++k)
        t.emplace_back(cc.edge[k].x / cc.edge[k].z, cc.edge[k].y / cc.edge[k].z);
    if (polygon_area(t) < 0) std::swap(t[1], t[2]);
    return t;
}

Polygon scaled(const Polygon& p, double s) {
    Polygon out;
    for (const dvec2& v : p)
        out.push_back(s * v);
    if (polygon_area(out) < 0) std::reverse(out.begin(), out.end());
    return out;
}

// The exit field of the order for the unit inputs s and p of the incident wave: refraction in,
// the three faces, refraction out.
void order_field(const WaveMaterial& m, const CubeCorner& cc, const dvec3& wi, cplx metal,
                 Order& o) {
    const Face face = Face(m.prism_reflection);
    dvec3 sIn, pIn, sOut, pOut;
    sp_basis(-wi, dvec3(0, 0, 1), sIn, pIn);
    for (int in = 0; in < 2; ++in) {
        const dvec3& e0 = in == 0 ? sIn : pIn;
        Field e = {e0.x, e0.y, e0.z};
        dvec3 k = -wi;
        e = transmit_field(e, k, dvec3(0, 0, 1), 1.0, m.ior);
        for (int step = 0; step < 3; ++step)
            e = reflect_field(e, k, cc.e[o.faces[size_t(step)]], m.ior, face, metal);
        e = transmit_field(e, k, dvec3(0, 0, -1), m.ior, 1.0);
        o.field[size_t(in)] = e;
        o.exit_dir = k;
    }
    sp_basis(o.exit_dir, dvec3(0, 0, 1), sOut, pOut);
    for (int in = 0; in < 2; ++in) {
        const Field& e = o.field[size_t(in)];
        o.jones[0][size_t(in)] = e[0] * sOut.x + e[1] * sOut.y + e[2] * sOut.z;
        o.jones[1][size_t(in)] = e[0] * pOut.x + e[1] * pOut.y + e[2] * pOut.z;
    }
}

// The order's polygons, exit direction and phase, or false when it has no area or its light
// cannot leave the top surface.
bool trace_polygons(const WaveMaterial& m, const CubeCorner& cc, const Pupil& pupil, double scale,
                    Order& o) {
    dvec3 last;
    if (!order_directions(cc, pupil.d, o.faces, last)) return false;
    Polygon poly = unit_aperture(cc);
    const double unitArea = polygon_area(poly);
    for (int c = 0; c < kConstraints && poly.size() >= 3; ++c) {
        std::vector<double> f;
        for (const dvec2& v : poly)
            f.push_back(constraint(cc, o.faces, trace_order(cc, pupil.d, o.faces, v), c));
        poly = clip_polygon(poly, f);
    }
    if (poly.size() < 3 || polygon_area(poly) < 1e-12 * unitArea) return false;
    const dvec2 gxy = m.ior * dvec2(last.x, last.y);
    if (!(glm::dot(gxy, gxy) < 1.0)) return false; // totally reflected at the top surface
    o.inner_exit = last;
    o.g = gxy;
    const double k0 = 2.0 * kPi / pupil.lambda_um;
    Polygon exitPoly;
    o.vertex_phase.clear();
    for (const dvec2& v : poly) {
        const OrderRay r = trace_order(cc, pupil.d, o.faces, v);
        const dvec2 x = scale * dvec2(r.exit.x, r.exit.y);
        exitPoly.push_back(x);
        // The incident wave's phase at the entry point plus the optical path inside.
        const double phase =
            k0 * scale * (-glm::dot(dvec2(pupil.wi.x, pupil.wi.y), v) + m.ior * r.length);
        o.vertex_phase.push_back(phase);
    }
    o.phase = o.vertex_phase[0] - k0 * glm::dot(o.g, exitPoly[0]);
    o.entry = scaled(poly, scale);
    o.exit = exitPoly;
    if (polygon_area(o.exit) < 0) {
        std::reverse(o.exit.begin(), o.exit.end());
        std::reverse(o.vertex_phase.begin(), o.vertex_phase.end());
    }
    return true;
}

} // namespace

double aperture_scale(const CubeCorner& cc, double pitchUm) {
    const Polygon t = unit_aperture(cc);
    // Vertices 1 and 2 (edges 1 and 2) lie in face 0, whatever order unit_aperture keeps.
    const dvec2 v1(cc.edge[1].x / cc.edge[1].z, cc.edge[1].y / cc.edge[1].z);
    const dvec2 v2(cc.edge[2].x / cc.edge[2].z, cc.edge[2].y / cc.edge[2].z);
    const double height = 2.0 * polygon_area(t) / glm::length(v2 - v1);
    return pitchUm / height;
}

Pupil exit_pupil(const WaveMaterial& m, const CubeCorner& cc, const dvec3& wi, double lambdaUm) {
    check_material(m);
    if (!(wi.z > 0 && std::abs(glm::length(wi) - 1.0) < 1e-9))
        throw InputError("wi: expected a unit direction above the sheet (wi.z > 0)");
    if (!(lambdaUm > 0 && std::isfinite(lambdaUm)))
        throw InputError("lambda " + std::to_string(lambdaUm) + ": expected a positive length");
    Pupil pupil;
    pupil.lambda_um = lambdaUm;
    pupil.wi = wi;
    const double scale = aperture_scale(cc, m.pitch_um);
    pupil.aperture = scaled(unit_aperture(cc), scale);
    pupil.cell_area = polygon_area(pupil.aperture);
    const Fresnel in = fresnel(wi.z, 1.0, m.ior);
    const double gain = (m.ior * in.cosT.real()) / wi.z;
    pupil.ts = gain * std::norm(in.ts);
    pupil.tp = gain * std::norm(in.tp);
    // Snell's law: the transverse component wi_xy / eta, downward.
    const dvec2 dxy = -dvec2(wi.x, wi.y) / m.ior;
    pupil.d = dvec3(dxy, -std::sqrt(std::max(0.0, 1.0 - glm::dot(dxy, dxy))));
    const cplx metal = m.prism_reflection == int(Face::kMetal)
                           ? metal_index(m.metal_reflectance, m.ior)
                           : cplx(0.0);
    std::array<int, 3> faces = {0, 1, 2};
    do {
        Order o;
        o.faces = faces;
        if (!trace_polygons(m, cc, pupil, scale, o)) continue;
        order_field(m, cc, wi, metal, o);
        pupil.orders.push_back(o);
    } while (std::next_permutation(faces.begin(), faces.end()));
    return pupil;
}

double pupil_energy(const Pupil& pupil) {
    double e = 0;
    for (const Order& o : pupil.orders) {
        double f = 0;
        for (const Field& col : o.field)
            for (const cplx& c : col)
                f += std::norm(c);
        e += polygon_area(o.exit) * 0.5 * f;
    }
    return e / pupil.cell_area;
}

// ---- Far field ------------------------------------------------------------------------------

FarField::FarField(const Pupil& p) : pupil(p), k0(2.0 * kPi / p.lambda_um) {
    for (const Order& o : p.orders)
        transforms.emplace_back(o.exit);
}

std::array<Field, 2> FarField::amplitude(const dvec2& sxy) const {
    std::array<Field, 2> u{};
    for (size_t j = 0; j < transforms.size(); ++j) {
        const Order& o = pupil.orders[j];
        const cplx f = transforms[j](k0 * (sxy - o.g)) * cplx(std::cos(o.phase), std::sin(o.phase));
        for (int in = 0; in < 2; ++in)
            for (int c = 0; c < 3; ++c)
                u[size_t(in)][size_t(c)] += o.field[size_t(in)][size_t(c)] * f;
    }
    return u;
}

double FarField::intensity(const dvec2& sxy) const {
    const std::array<Field, 2> u = amplitude(sxy);
    double sum = 0;
    for (const Field& col : u)
        for (const cplx& c : col)
            sum += std::norm(c);
    return 0.5 * sum;
}

double FarField::ra(const dvec3& wo) const {
    if (!(wo.z > 0)) return 0.0;
    const double lambda = pupil.lambda_um;
    return pupil.wi.z * wo.z * intensity(dvec2(wo.x, wo.y)) / (lambda * lambda * pupil.cell_area);
}

std::vector<double> far_field_grid(const Pupil& pupil, int n, double halfWidthDeg) {
    if (!(n >= 1 && n <= 4096))
        throw InputError("n " + std::to_string(n) + ": expected a whole number in [1, 4096]");
    if (!(halfWidthDeg > 0 && halfWidthDeg <= 30))
        throw InputError("halfWidthDeg " + std::to_string(halfWidthDeg) +
                         ": expected a number in (0, 30]");
    const FarField ff(pupil);
    const double half = halfWidthDeg * kPi / 180.0;
    std::vector<double> grid;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const dvec2 sxy = dvec2(pupil.wi.x, pupil.wi.y) +
                              half * dvec2(2.0 * (i + 0.5) / n - 1.0, 2.0 * (j + 0.5) / n - 1.0);
            const double z2 = 1.0 - glm::dot(sxy, sxy);
            grid.push_back(z2 > 0 ? ff.ra(dvec3(sxy, std::sqrt(z2))) : 0.0);
        }
    return grid;
}

dvec3 observation_direction(const dvec3& wi, double observationRad, double chi) {
    dvec3 a = dvec3(0, 0, 1) - wi * wi.z;
    a = glm::length(a) > 1e-12 ? glm::normalize(a) : dvec3(1, 0, 0);
    const dvec3 b = glm::cross(wi, a);
    return std::cos(observationRad) * wi +
           std::sin(observationRad) * (std::cos(chi) * a + std::sin(chi) * b);
}

double tail_perimeter(const Polygon& p, const dvec3& wi) {
    dvec3 a = dvec3(0, 0, 1) - wi * wi.z;
    a = glm::length(a) > 1e-12 ? glm::normalize(a) : dvec3(1, 0, 0);
    const dvec3 b = glm::cross(wi, a);
    const dvec2 ah = glm::normalize(dvec2(a.x, a.y)), bh = glm::normalize(dvec2(b.x, b.y));
    const double c = wi.z;
    double sum = 0;
    for (size_t j = 0; j < p.size(); ++j) {
        const dvec2 edge = p[(j + 1) % p.size()] - p[j];
        const double len = glm::length(edge);
        if (len <= 0) continue;
        const dvec2 n(edge.y / len, -edge.x / len);
        const double na = glm::dot(n, ah) / c, nb = glm::dot(n, bh);
        sum += len * std::sqrt(na * na + nb * nb);
    }
    return sum;
}

namespace {

// One edge of an order's exit polygon on its line: the line's canonical unit normal n and offset
// c = n.x, the interval [t0, t1] along tau = (-n.y, n.x), and the field's jump across the line
// toward +n (minus the order's field where its outward normal is +n, plus it where -n).
struct LineSegment {
    dvec2 n;
    double c, t0, t1;
    std::array<Field, 2> jump;
};

std::vector<LineSegment> line_segments(const Pupil& pupil) {
    std::vector<LineSegment> list;
    for (const Order& o : pupil.orders) {
        const cplx phase(std::cos(o.phase), std::sin(o.phase));
        for (size_t j = 0; j < o.exit.size(); ++j) {
            const dvec2 a = o.exit[j], b = o.exit[(j + 1) % o.exit.size()];
            const double len = glm::length(b - a);
            if (len <= 0) continue;
            LineSegment seg;
            seg.n = dvec2(b.y - a.y, a.x - b.x) / len; // outward for counter-clockwise
            double sign = -1;
            if (seg.n.x < -1e-12 || (std::abs(seg.n.x) <= 1e-12 && seg.n.y < 0)) {
                seg.n = -seg.n;
                sign = 1;
            }
            const dvec2 tau(-seg.n.y, seg.n.x);
            seg.c = glm::dot(seg.n, a);
            seg.t0 = std::min(glm::dot(tau, a), glm::dot(tau, b));
            seg.t1 = std::max(glm::dot(tau, a), glm::dot(tau, b));
            for (int in = 0; in < 2; ++in)
                for (int c = 0; c < 3; ++c)
                    seg.jump[size_t(in)][size_t(c)] = sign * phase * o.field[size_t(in)][size_t(c)];
            list.push_back(seg);
        }
    }
    return list;
}

// The integral along one line (its segments) of the mean over inputs of |jump|^2.
double line_integral(const std::vector<const LineSegment*>& line) {
    std::vector<double> cuts;
    for (const LineSegment* s : line) {
        cuts.push_back(s->t0);
        cuts.push_back(s->t1);
    }
    std::sort(cuts.begin(), cuts.end());
    double sum = 0;
    for (size_t k = 0; k + 1 < cuts.size(); ++k) {
        const double mid = 0.5 * (cuts[k] + cuts[k + 1]);
        std::array<Field, 2> jump{};
        for (const LineSegment* s : line)
            if (s->t0 < mid && mid < s->t1)
                for (int in = 0; in < 2; ++in)
                    for (int c = 0; c < 3; ++c)
                        jump[size_t(in)][size_t(c)] += s->jump[size_t(in)][size_t(c)];
        double norm = 0;
        for (const Field& col : jump)
            for (const cplx& v : col)
                norm += std::norm(v);
        sum += 0.5 * norm * (cuts[k + 1] - cuts[k]);
    }
    return sum;
}

} // namespace

double tail_constant(const Pupil& pupil) {
    const std::vector<LineSegment> segments = line_segments(pupil);
    const dvec3 wi = pupil.wi;
    dvec3 a = dvec3(0, 0, 1) - wi * wi.z;
    a = glm::length(a) > 1e-12 ? glm::normalize(a) : dvec3(1, 0, 0);
    const dvec3 b = glm::cross(wi, a);
    const dvec2 ah = glm::normalize(dvec2(a.x, a.y)), bh = glm::normalize(dvec2(b.x, b.y));
    const double tol = 1e-9 * std::sqrt(pupil.cell_area);
    std::vector<bool> used(segments.size(), false);
    double k = 0;
    for (size_t i = 0; i < segments.size(); ++i) {
        if (used[i]) continue;
        std::vector<const LineSegment*> line;
        for (size_t j = i; j < segments.size(); ++j)
            if (!used[j] && glm::length(segments[j].n - segments[i].n) < 1e-9 &&
                std::abs(segments[j].c - segments[i].c) < tol) {
                used[j] = true;
                line.push_back(&segments[j]);
            }
        const dvec2 n = segments[i].n;
        const double na = glm::dot(n, ah) / wi.z, nb = glm::dot(n, bh);
        k += std::sqrt(na * na + nb * nb) * line_integral(line);
    }
    return k;
}

} // namespace wave
} // namespace sim
} // namespace retroprism
