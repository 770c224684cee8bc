// microgeometry.cpp: the microgeometry simulator (see microgeometry.h for what is simulated).
#include "microgeometry.h"

#include "cube_corner.h"
#include "tracing.h"
#include "variates.h"

#include "linalg.h"
#include "parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace retroprism {
namespace sim {

using namespace tracing; // the pieces shared with the wavefront

namespace {

// Angle between unit vectors, accurate near 0 and pi.
double angle_between(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

} // namespace

// ---- Sheet ------------------------------------------------------------------------------------

Sheet sheet_from_params(const Params& raw, int channel) {
    const Params p = sanitize(raw);
    Sheet s;
    s.alpha = std::max(p.roughness, f64::RP_MIN_ALPHA);
    s.eta = p.ior;
    s.prism_reflection = p.prism_reflection;
    s.metal_reflectance = p.metal_reflectance;
    s.era_mode = p.era_mode;
    s.orientation_deg = p.orientation;
    s.cant_deg = p.cant_angle;
    s.dihedral_arcmin = p.dihedral_error;
    s.dihedral_spread_arcmin = p.dihedral_spread;
    s.kd = p.diffuse_color[size_t(std::clamp(channel, 0, 2))];
    return s;
}

// ---- Top surface: Smith microsurface random walk ------------------------------------------------

double smith_lambda(const dvec3& w, double alpha) {
    if (w.z >= 1.0) return 0.0;
    if (w.z <= -1.0) return -1.0;
    const double tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
    const double l = f64::rp_beckmann_lambda(tan2, alpha);
    return w.z > 0 ? l : -1.0 - l;
}

// Slope x of a visible normal of the standard Beckmann surface (alpha = 1) seen from polar angle
// theta in (0, pi) in the xz-plane: the inverse of the visible-slope CDF (Heitz & d'Eon 2014)
// C(x) = G(x) / G(cot), G(x) = (sin exp(-x^2) / sqrt(pi) + cos erfc(-x)) / 2 for x <= cot,
// written with erfc so that it holds for views from below the mean plane (cos < 0) too. Solved
// by Newton's method safeguarded by bisection, to |G(x) - u G(cot)| <= 1e-14 G(cot).
double tracing::visible_slope_x(double cosT, double sinT, double u) {
    auto g = [&](double x) {
        return 0.5 * (sinT * std::exp(-x * x) * kInvSqrtPi + cosT * std::erfc(-x));
    };
    const double cot = cosT / sinT;
    double lo = -9.0, hi = std::min(cot, 9.0);
    if (!(hi > lo)) return hi; // a view so far below that nothing is visible
    const double total = g(hi);
    if (!(total > 0)) return hi;
    const double target = u * total;
    // Start: the Gaussian quantile (exact for a view along the normal), inside the bracket.
    double x =
        cosT > 0 ? f64::rp_erfinv_giles(std::clamp(2.0 * u - 1.0, -0.999999, 0.999999)) : hi - 0.5;
    if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
    for (int it = 0; it < 200; ++it) {
        const double v = g(x) - target;
        if (std::abs(v) <= 1e-14 * total) break;
        if (v > 0)
            hi = x;
        else
            lo = x;
        if (hi - lo < 1e-13) break;
        const double dv = std::exp(-x * x) * kInvSqrtPi * (cosT - x * sinT);
        double xn = dv > 0 ? x - v / dv : 0.5 * (lo + hi);
        if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
        x = xn;
    }
    return x;
}

namespace {

// Heights of the microsurface, and the next intersection of a ray of direction w (Heitz et al.
// 2016, Algorithm 2): with C1 = C(h) the height's CDF and Lambda = Lambda(w), an upward ray leaves
// the microsurface with probability G1 = C1^Lambda, else it hits at the height of CDF C1 / q,
// q = (1 - u)^(1 / Lambda) <= C1 uniform u; a downward ray (Lambda <= -1) always hits, at the
// height of CDF C1 (1 - u)^(-1 / Lambda). Any height distribution gives the same Smith
// microsurface (section 4.1), and the walk needs the heights only through their CDF: it keeps the
// depth l = -log C(h) >= 0 (0 above every point), in which, with E = -log(1 - u) a standard
// exponential variate (the ziggurat of sim/variates.h, no logarithm or power), the upward ray
// leaves when E >= Lambda l, else goes up to l - E / Lambda, and the downward ray goes down to
// l + E / -Lambda. The walk from inside the sheet is the mirror image (heights -h): its depth is
// -log(1 - C(h)) = -log(-expm1(-l)) of the depth l from outside (a symmetric distribution of
// heights), converted when the ray changes sides and the next step needs it.
struct Depth {
    double l = 0.0;      // -log C of the height, seen from side `outside`
    bool outside = true; // the side whose heights l measures
};

// The next step of a ray of direction w (in the frame of its side: w.z > 0 away from its medium)
// from depth d on side `outside`: true when it leaves the microsurface, else d is the depth of
// the intersection. An upward ray with Lambda = 0 (steeper than every microfacet) always leaves,
// a grazing one hits at once; E is drawn only when the outcome is random.
bool next_depth(const dvec3& w, bool outside, double alpha, Depth& d, Rng& rng) {
    if (std::abs(w.z) < 1e-12) return false; // grazing: hits at once
    const double lambda = walk_lambda(w, alpha);
    if (w.z > 0 && !(lambda > 0)) return true;
    const double e = exponential_variate(rng);
    if (d.outside != outside) {
        d.l = depth_flip(d.l);
        d.outside = outside;
    }
    if (w.z > 0) {
        if (e >= lambda * d.l) return true;
        d.l = std::max(0.0, d.l - e / lambda);
    } else {
        d.l += lambda == -1.0 ? e : e / -lambda; // for Lambda = -1 (a direction steeper than
                                                 // the microsurface's slopes) without division
    }
    return false;
}

} // namespace

namespace {

// A uniform point (x, y) of the open unit disk, by rejection from the square; its x^2 + y^2.
double disk_point(Rng& rng, double& x, double& y) {
    double r2;
    do {
        const UniformPair p = uniform_pair(rng);
        x = 2.0 * p.u - 1.0;
        y = 2.0 * p.v - 1.0;
        r2 = x * x + y * y;
    } while (!(r2 < 1.0));
    return r2;
}

// A uniform direction (c, s) = (cos psi, sin psi) of the plane, psi uniform in [0, 2 pi): a
// uniform point (x, y) of the unit disk by rejection, its angle doubled ((x^2 - y^2, 2 x y) /
// r^2: psi = 2 atan2(y, x) is uniform mod 2 pi as atan2 is uniform in (-pi, pi]).
void uniform_rotation(Rng& rng, double& c, double& s) {
    double x, y, r2;
    do {
        r2 = disk_point(rng, x, y);
    } while (!(r2 > 1e-200));
    const double inv = 1.0 / r2;
    c = (x - y) * (x + y) * inv;
    s = 2.0 * x * y * inv;
}

// Slope x of a visible normal of the standard Beckmann surface seen from above the mean plane
// (cosT > 0, sinT > 0; any common positive factor of the two), density p(x) proportional to
// exp(-x^2) (cosT - x sinT)_+, sampled exactly by rejection from the mixture q(x) = cosT exp(-x^2)
// (all x) + sinT |x| exp(-x^2) (x < 0 only), of masses cosT sqrt(pi) and sinT / 2: for x < 0, q =
// p; for x > 0, p / q = (1 - x tanT)_+. The Gaussian component draws from `gauss` (an iid stream of
// N(0, 1/2)), the other is -sqrt(E), E exponential (P(|x| > t) = exp(-t^2)). Acceptance is
// mass(p) / mass(q): 1 at normal and grazing views, 0.865 at worst (62.7 degrees); no exp or
// erfc is evaluated.
template <class Gauss>
double visible_slope_x_above(double cosT, double sinT, Rng& rng, Gauss& gauss) {
    const double wGauss = cosT * kSqrtPi;
    const double pGauss = wGauss / (wGauss + 0.5 * sinT);
    for (;;) {
        const UniformPair p = uniform_pair(rng); // the component, the acceptance
        if (p.u >= pGauss) return -std::sqrt(exponential_variate(rng));
        const double x = gauss();
        // Accepted when x <= 0 or by the ratio p / q: one branch, taken mostly.
        if ((x <= 0) | (p.v * cosT < cosT - x * sinT)) return x;
    }
}

} // namespace

dvec3 sample_visible_normal(const dvec3& w, double alpha, Rng& rng) {
    // The view of the standard surface (the stretched w): azimuth that of w, polar angle theta
    // with (cos, sin) proportional to (w.z, alpha |w.xy|), left unnormalised where only their
    // ratio matters (the sampling from above, the test for a view along the normal).
    const double rxy = std::sqrt(w.x * w.x + w.y * w.y);
    const double cosS = w.z, sinS = alpha * rxy;
    // Slope y (and x at normal view): Gaussians of density exp(-s^2) / sqrt(pi) (variance 1/2).
    auto gauss = [&]() { return kInvSqrt2 * normal_variate(rng); };
    const double sy = gauss();
    double sx;
    double cosPhi = 1.0, sinPhi = 0.0;
    if (sinS * sinS < 1e-24 * (cosS * cosS + sinS * sinS)) { // sin(theta) < 1e-12
        sx = gauss();
    } else {
        // Views from above by rejection; from below (the random walk's masked rays) by the
        // inversion of the CDF.
        if (cosS > 0) {
            sx = visible_slope_x_above(cosS, sinS, rng, gauss);
        } else {
            const double n = 1.0 / std::sqrt(cosS * cosS + sinS * sinS);
            sx = visible_slope_x(cosS * n, sinS * n, rng.uniform_open());
        }
        const double inv = 1.0 / rxy;
        cosPhi = w.x * inv;
        sinPhi = w.y * inv;
    }
    const double tx = alpha * (cosPhi * sx - sinPhi * sy);
    const double ty = alpha * (sinPhi * sx + cosPhi * sy);
    return glm::normalize(dvec3(-tx, -ty, 1.0));
}

Crossing cross_top_surface(const Sheet& sheet, const dvec3& dir, bool from_outside, Rng& rng) {
    Crossing out;
    dvec3 w = dir;
    bool outside = from_outside;
    Depth depth; // above (outside) / below (inside) every point of the microsurface
    depth.outside = outside;
    for (int order = 0; order <= kMaxWalkOrder; ++order) {
        if (next_depth(outside ? w : -w, outside, sheet.alpha, depth, rng)) {
            out.dir = w;
            out.outside = outside;
            out.order = order;
            return out;
        }
        if (order == kMaxWalkOrder) break;
        // Scattering at a visible microfacet: normal seen from wIn on this side.
        const dvec3 wIn = -w;
        const dvec3 m = outside ? sample_visible_normal(wIn, sheet.alpha, rng)
                                : -sample_visible_normal(-wIn, sheet.alpha, rng);
        const double c = std::max(glm::dot(wIn, m), 0.0);
        const double fr = outside ? f64::rp_fresnel_dielectric(c, sheet.eta)
                                  : f64::rp_fresnel_internal(c, sheet.eta);
        if (rng.uniform() < fr) {
            w = glm::normalize(2.0 * c * m - wIn);
        } else {
            w = refract_dir(wIn, m, c, outside ? 1.0 / sheet.eta : sheet.eta);
            outside = !outside;
        }
    }
    out.dir = w;
    out.outside = outside;
    out.order = kMaxWalkOrder;
    out.trapped = true;
    return out;
}

// ---- Cube corner
// ---------------------------------------------------------------------------------

PrismOutcome trace_prism(const Sheet& sheet, const dvec3& d, Rng& rng, dvec3* exit) {
    if (!(d.z < 0)) return kPrismMiss;
    // b_k = d.e_k, e_k = (sqrt(2/3) v_k, 1/sqrt3), v_k the vertex directions at psi + 120 k
    // degrees, psi the orientation of vertex 0.
    double b[3];
    double roulette = -1.0; // the uniform of the faces' Russian roulette when drawn in advance
    if (sheet.era_mode == f64::RP_ERA_AVERAGED && sheet.cant_deg == 0.0 &&
        sheet.dihedral_arcmin == 0.0 && sheet.dihedral_spread_arcmin == 0.0) {
        const UniformPair turn = uniform_pair(rng); // the turn, the faces' roulette
        averaged_cube_b(d, turn.u, b);
        roulette = turn.v;
    } else {
        // The orientation: fixed, one of the matched pair, or uniform (a canted cube, whose
        // only symmetry is its mirror plane, or one with dihedral errors).
        double c0, s0;
        if (sheet.era_mode == f64::RP_ERA_AVERAGED) {
            uniform_rotation(rng, c0, s0);
        } else {
            double psi = sheet.orientation_deg * (kPi / 180.0);
            if (sheet.era_mode == f64::RP_ERA_MATCHED_PAIR && rng.uniform() < 0.5) psi += kPi;
            c0 = std::cos(psi);
            s0 = std::sin(psi);
        }
        if (sheet.dihedral_spread_arcmin != 0.0) {
            // This prism's own dihedral errors: each of the three about the sheet's mean, with
            // the sheet's deviation, independently.
            double errors[3];
            for (double& e : errors)
                e = sheet.dihedral_arcmin + sheet.dihedral_spread_arcmin * normal_variate(rng);
            return trace_cube_corner(sheet, cube_corner(sheet.cant_deg, errors, std::atan2(s0, c0)),
                                     d, rng, exit);
        }
        if (sheet.cant_deg != 0.0 || sheet.dihedral_arcmin != 0.0)
            return trace_cube_corner(
                sheet, cube_corner(sheet.cant_deg, sheet.dihedral_arcmin, std::atan2(s0, c0)), d,
                rng, exit);
        const double vx[3] = {c0, -0.5 * c0 - kSin120 * s0, -0.5 * c0 + kSin120 * s0};
        const double vy[3] = {s0, kSin120 * c0 - 0.5 * s0, -kSin120 * c0 - 0.5 * s0};
        for (int k = 0; k < 3; ++k)
            b[k] = kSqrt2Over3 * (vx[k] * d.x + vy[k] * d.y) + kInvSqrt3 * d.z;
    }
    // Uniform entry point on the aperture (two draws), and the faces hit.
    const double u = rng.uniform(), v = rng.uniform();
    const PrismOutcome o =
        cube_outcome<false>(sheet.prism_reflection, sheet.eta, sheet.metal_reflectance, b, u, v,
                            [&]() { return roulette >= 0 ? roulette : rng.uniform(); });
    if (o == kPrismRetro && exit) *exit = -d;
    return o;
}

// ---- Paths -------------------------------------------------------------------------------------

const char* fate_name(int fate) {
    static const char* names[kFates] = {"exit_surface",         "exit_retro",
                                        "exit_diffuse",         "absorbed_substrate",
                                        "absorbed_prism_faces", "trapped"};
    return fate >= 0 && fate < kFates ? names[fate] : "?";
}

const char* channel_name(int channel) {
    static const char* names[kChannels] = {"surface", "surface_single", "retro", "diffuse"};
    return channel >= 0 && channel < kChannels ? names[channel] : "?";
}

[[gnu::flatten]] bool tracing::below_surface(const Sheet& sheet, Below where, const dvec3& d,
                                             bool& visited, int& event, Path& p, Rng& rng,
                                             dvec3& up) {
    for (;;) {
        if (!count_event(event)) return false; // trapped
        if (where == Below::kPrisms) {
            const PrismOutcome o = trace_prism(sheet, d, rng, &up);
            if (o == kPrismRetro) {
                ++p.retroreflections;
                return true;
            }
            if (o == kPrismAbsorbed) {
                p.fate = kFateAbsorbedFaces;
                return false;
            }
            if (o == kPrismTransmitted) ++p.face_transmissions;
            where = Below::kSubstrate;
            continue;
        }
        visited = true;
        ++p.substrate_hits;
        if (rng.uniform() >= sheet.kd) {
            p.fate = kFateAbsorbedSubstrate;
            return false;
        }
        // Lambertian re-emission into the sheet (Malley's method: a uniform point of the unit
        // disk, by rejection, lifted to the hemisphere).
        double x, y;
        const double r2 = disk_point(rng, x, y);
        up = dvec3(x, y, std::sqrt(1.0 - r2));
        if (sheet.upward_through_prisms) {
            // The adjoint of the way down along -up.
            const PrismOutcome o = trace_prism(sheet, -up, rng);
            if (o == kPrismRetro) continue; // back to the substrate
            if (o == kPrismAbsorbed) {
                p.fate = kFateAbsorbedFaces;
                return false;
            }
            if (o == kPrismTransmitted) ++p.face_transmissions;
        }
        return true;
    }
}

[[gnu::flatten]] bool tracing::after_crossing(const Sheet& sheet, const Crossing& c, bool upward,
                                              bool& visited, int& event, Path& p, Rng& rng,
                                              dvec3& up) {
    Below where;
    if (leaves_sheet(sheet, c, upward, visited, p, where)) return false;
    // Below the surface, then the upward crossing: one event.
    return below_surface(sheet, where, c.dir, visited, event, p, rng, up) && count_event(event);
}

// Flattened: the walk, the prism trace and the variates inlined into the path's loop (identical
// results, fewer instructions per ray: no calls and register spills per event).
[[gnu::flatten]] Path trace_path(const Sheet& sheet, const dvec3& wi, Rng& rng) {
    Path p;
    Crossing c = cross_top_surface(sheet, -wi, true, rng);
    bool upward = false, visited = false;
    int event = 0;
    dvec3 up(0.0);
    while (!c.trapped && after_crossing(sheet, c, upward, visited, event, p, rng, up)) {
        c = cross_top_surface(sheet, up, false, rng);
        upward = true;
    }
    return p; // its fate, or trapped
}

// ---- Grids
// ----------------------------------------------------------------------------------------

namespace {

// Concentric map of Shirley & Chiu: square [-1, 1]^2 to the unit disk, area-preserving up to
// the factor pi / 4, and its inverse.
dvec2 square_to_disk(double a, double b) {
    if (a == 0 && b == 0) return dvec2(0.0);
    double r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = (kPi / 4) * (b / a);
    } else {
        r = b;
        phi = kPi / 2 - (kPi / 4) * (a / b);
    }
    return dvec2(r * std::cos(phi), r * std::sin(phi));
}

dvec2 disk_to_square(double x, double y) {
    const double r = std::sqrt(x * x + y * y);
    if (r == 0) return dvec2(0.0);
    // The sector by comparison, and its angle (atan2(y, x) less a multiple of pi / 2, in
    // [-pi/4, pi/4]) by atan of a ratio in [-1, 1]: cheaper than atan2.
    if (std::abs(x) > std::abs(y)) {
        const double t = r * std::atan(y / x) * (4 / kPi);
        return x > 0 ? dvec2(r, t) : dvec2(-r, -t);
    }
    const double t = r * std::atan(x / y) * (4 / kPi);
    return y > 0 ? dvec2(t, r) : dvec2(-t, -r);
}

} // namespace

bool Grid::params(const dvec3& w, double& x, double& y) const {
    switch (kind) {
    case kGnomonic: {
        const double cp = glm::dot(w, c);
        if (!(cp > 0)) return false;
        x = glm::dot(w, e1) / cp;
        y = glm::dot(w, e2) / cp;
        return true;
    }
    case kDisk: {
        if (!(w.z >= 0)) return false;
        const dvec2 s = disk_to_square(w.x, w.y);
        x = s.x;
        y = s.y;
        return true;
    }
    case kStrip: {
        x = std::atan2(glm::dot(w, e1), glm::dot(w, c));
        y = std::asin(std::clamp(glm::dot(w, e2), -1.0, 1.0));
        return true;
    }
    case kCone: {
        x = angle_between(w, c);
        y = std::atan2(glm::dot(w, e2), glm::dot(w, e1));
        if (y < 0) y += 2 * kPi;
        return true;
    }
    }
    return false;
}

dvec3 Grid::direction(double x, double y, double& jacobian) const {
    switch (kind) {
    case kGnomonic: {
        const double q = 1.0 + x * x + y * y;
        jacobian = 1.0 / (q * std::sqrt(q));
        return glm::normalize(c + x * e1 + y * e2);
    }
    case kDisk: {
        const dvec2 p = square_to_disk(x, y);
        const double z = std::sqrt(std::max(0.0, 1.0 - p.x * p.x - p.y * p.y));
        jacobian = z > 0 ? (kPi / 4) / z : 0.0;
        return dvec3(p.x, p.y, z);
    }
    case kStrip: {
        jacobian = std::cos(y);
        return std::cos(y) * (std::sin(x) * e1 + std::cos(x) * c) + std::sin(y) * e2;
    }
    case kCone: {
        jacobian = std::sin(x);
        return std::cos(x) * c + std::sin(x) * (std::cos(y) * e1 + std::sin(y) * e2);
    }
    }
    jacobian = 0;
    return c;
}

int Grid::cell_of(const dvec3& w) const {
    if (kind == kCone) return glm::dot(w, c) >= std::cos(x1) ? 0 : -1;
    if (kind == kStrip) {
        // Most directions are far outside the band: y = asin(t), t = w.e2, and |asin t| >= |t|
        // (also as computed: a faithfully rounded asin(t) is still >= t, t being representable), so
        // t > y1 >= 0 or t < y0 <= 0 is outside without the asin and atan2 of params.
        const double t = glm::dot(w, e2);
        if ((y1 >= 0 && t > y1) || (y0 <= 0 && t < y0)) return -1;
    }
    double x, y;
    if (kind == kGnomonic) {
        // params' gnomonic case, inline: slopes, rejected before the second division.
        const double cp = glm::dot(w, c);
        if (!(cp > 0)) return -1;
        x = glm::dot(w, e1) / cp;
        if (!(x >= x0 && x < x1)) return -1;
        y = glm::dot(w, e2) / cp;
    } else if (!params(w, x, y)) {
        return -1;
    }
    if (!(x >= x0 && x < x1 && y >= y0 && y < y1)) {
        // The disk's outer edge (x or y = 1) belongs to the last cell.
        if (kind == kDisk && x >= x0 && x <= x1 && y >= y0 && y <= y1) {
            x = std::min(x, std::nextafter(x1, x0));
            y = std::min(y, std::nextafter(y1, y0));
        } else {
            return -1;
        }
    }
    // Cells per unit of each parameter: divisions off the path from w to the cell.
    const double perX = nx / (x1 - x0), perY = ny / (y1 - y0);
    const int i = std::min(nx - 1, int((x - x0) * perX));
    const int j = std::min(ny - 1, int((y - y0) * perY));
    return j * nx + i;
}

dvec3 Grid::cell_centre(int cell) const {
    const int i = cell % nx, j = cell / nx;
    double jac;
    if (kind == kCone) return c;
    return direction(x0 + (i + 0.5) * (x1 - x0) / nx, y0 + (j + 0.5) * (y1 - y0) / ny, jac);
}

Grid gnomonic_grid(const std::string& name, const dvec3& centre, const dvec3& e1, const dvec3& e2,
                   double halfX, double halfY, int nx, int ny) {
    Grid g;
    g.kind = Grid::kGnomonic;
    g.name = name;
    g.c = centre;
    g.e1 = e1;
    g.e2 = e2;
    g.x0 = -halfX;
    g.x1 = halfX;
    g.y0 = -halfY;
    g.y1 = halfY;
    g.nx = nx;
    g.ny = ny;
    return g;
}

Grid disk_grid(const std::string& name, int n) {
    Grid g;
    g.kind = Grid::kDisk;
    g.name = name;
    g.nx = g.ny = n;
    return g;
}

Grid strip_grid(const std::string& name, const dvec3& c, const dvec3& e1, int n,
                double halfWidthRad) {
    Grid g;
    g.kind = Grid::kStrip;
    g.name = name;
    g.c = c;
    g.e1 = e1;
    g.e2 = glm::normalize(glm::cross(c, e1));
    g.x0 = -kPi / 2;
    g.x1 = kPi / 2;
    g.y0 = -halfWidthRad;
    g.y1 = halfWidthRad;
    g.nx = n;
    g.ny = 1;
    return g;
}

Grid cone_grid(const std::string& name, const dvec3& axis, double radiusRad) {
    Grid g;
    g.kind = Grid::kCone;
    g.name = name;
    g.c = glm::normalize(axis);
    // Any frame about the axis (Duff et al. 2017).
    const double sgn = g.c.z >= 0 ? 1.0 : -1.0;
    const double a = -1.0 / (sgn + g.c.z), b = g.c.x * g.c.y * a;
    g.e1 = dvec3(1.0 + sgn * g.c.x * g.c.x * a, sgn * b, -sgn * g.c.x);
    g.e2 = dvec3(b, sgn + g.c.y * g.c.y * a, -g.c.y);
    g.x0 = 0;
    g.x1 = radiusRad;
    g.y0 = 0;
    g.y1 = 2 * kPi;
    return g;
}

void lobe_frame(const dvec3& w, dvec3& ePar, dvec3& ePerp) {
    const double rxy = std::sqrt(w.x * w.x + w.y * w.y);
    ePerp = rxy > 0 ? dvec3(-w.y / rxy, w.x / rxy, 0.0) : dvec3(0.0, 1.0, 0.0);
    ePar = glm::cross(ePerp, w);
}

std::vector<Grid> standard_grids(const Sheet& sheet, const dvec3& wi, const GridOptions& opt) {
    // The analytic retro widths (isotropic alpha_o and anisotropic alpha_par, alpha_perp).
    Params p;
    p.roughness = sheet.alpha;
    p.ior = sheet.eta;
    f64::rp_material m = prepare_material(sanitize(p));
    f64::rp_incident iso, aniso;
    f64::rp_incident_setup(m, wi, iso);
    m.retro_anisotropic = 1;
    f64::rp_incident_setup(m, wi, aniso);
    const double hx = std::min(kLobeSpan * std::max(aniso.alphaPar, iso.alphaPar), kMaxSlope);
    const double hy = std::min(kLobeSpan * std::max(aniso.alphaPerp, iso.alphaPerp), kMaxSlope);
    std::vector<Grid> grids;
    dvec3 ePar, ePerp;
    lobe_frame(wi, ePar, ePerp);
    grids.push_back(gnomonic_grid("retro", wi, ePar, ePerp, hx, hy, opt.nLobe, opt.nLobe));
    const dvec3 wr(-wi.x, -wi.y, wi.z);
    dvec3 rPar, rPerp;
    lobe_frame(wr, rPar, rPerp);
    const double hm = std::min(kLobeSpan * 2.0 * sheet.alpha, kMaxSlope);
    grids.push_back(gnomonic_grid("mirror", wr, rPar, rPerp, hm, hm, opt.nLobe, opt.nLobe));
    grids.push_back(disk_grid("hemisphere", opt.nDisk));
    // The plane of incidence: x > 0 toward wi's azimuth (the light's side).
    const double rxy = std::sqrt(wi.x * wi.x + wi.y * wi.y);
    const dvec3 ex = rxy > 0 ? dvec3(wi.x / rxy, wi.y / rxy, 0.0) : dvec3(1.0, 0.0, 0.0);
    const double half = opt.stripHalfWidthDeg * kPi / 180.0;
    grids.push_back(strip_grid("in_plane", dvec3(0, 0, 1), ex, opt.nStrip, half));
    grids.push_back(strip_grid("across", wi, ePerp, opt.nStrip, half));
    return grids;
}

// ---- Simulation
// ----------------------------------------------------------------------------------

// A direction in the cone of half-angle r about c (frame e1, e2), with density proportional to
// its cos(theta) (z component): uniform in solid angle, then accepted with probability
// z / (largest z in the cone).
dvec3 tracing::sample_cone(const dvec3& c, const dvec3& e1, const dvec3& e2, double r, Rng& rng) {
    const double zMax = std::min(1.0, std::cos(std::max(0.0, std::acos(std::min(c.z, 1.0)) - r)));
    for (;;) {
        const double cosT = 1.0 - rng.uniform() * (1.0 - std::cos(r));
        const double sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
        const double phi = 2.0 * kPi * rng.uniform();
        const dvec3 w = cosT * c + sinT * (std::cos(phi) * e1 + std::sin(phi) * e2);
        if (w.z > 0 && rng.uniform() * zMax < w.z) return glm::normalize(w);
    }
}

int tracing::tally_counters(const Path& p, Tally& t, bool& single) {
    ++t.fates[size_t(p.fate)];
    t.substrate_hits += std::uint64_t(p.substrate_hits);
    t.face_transmissions += std::uint64_t(p.face_transmissions);
    t.internal_reflections += std::uint64_t(p.internal_reflections);
    single = false;
    if (p.fate == kFateSurface) {
        single = p.surface_order == 1;
        if (single) ++t.surface_single;
        return kSurface;
    }
    if (p.fate == kFateRetro) {
        if (p.retroreflections == 1 && p.internal_reflections == 0) ++t.retro_primary;
        if (p.retroreflections > 1) ++t.retro_multiple;
        return kRetro;
    }
    return p.fate == kFateDiffuse ? kDiffuse : -1;
}

// Flattened: the grids' lookups inlined.
[[gnu::flatten]] void tracing::tally_path(const Path& p, const std::vector<Grid>& grids, Tally& t) {
    bool single;
    const int channel = tally_counters(p, t, single);
    if (channel < 0) return;
    for (size_t g = 0; g < grids.size(); ++g) {
        const int cell = grids[g].cell_of(p.wo);
        if (cell < 0) continue;
        count_exit(t.counts[g].data(), cell, channel, single);
    }
}

void Tally::add(const Tally& o) {
    rays += o.rays;
    for (int f = 0; f < kFates; ++f)
        fates[size_t(f)] += o.fates[size_t(f)];
    retro_primary += o.retro_primary;
    retro_multiple += o.retro_multiple;
    surface_single += o.surface_single;
    substrate_hits += o.substrate_hits;
    face_transmissions += o.face_transmissions;
    internal_reflections += o.internal_reflections;
    if (counts.size() < o.counts.size()) counts.resize(o.counts.size());
    for (size_t g = 0; g < o.counts.size(); ++g) {
        if (counts[g].size() < o.counts[g].size()) counts[g].resize(o.counts[g].size(), 0);
        for (size_t i = 0; i < o.counts[g].size(); ++i)
            counts[g][i] += o.counts[g][i];
    }
}

Run simulate(const Sheet& sheet, const dvec3& wiIn, const std::vector<Grid>& grids,
             const RunOptions& opt) {
    const dvec3 wi = glm::normalize(wiIn);
    Run run;
    run.threads = thread_count(opt.threads);
    const std::uint64_t chunks = (opt.rays + kChunkRays - 1) / kChunkRays;
    run.threads = int(std::max<std::uint64_t>(1, std::min<std::uint64_t>(run.threads, chunks)));
    std::vector<Tally> local(size_t(run.threads));
    for (Tally& t : local) {
        t.counts.resize(grids.size());
        for (size_t g = 0; g < grids.size(); ++g)
            t.counts[g].assign(size_t(grids[g].cells()) * kChannels, 0);
    }
    dvec3 e1, e2;
    lobe_frame(wi, e1, e2);
    const bool wavefront =
        opt.tracer == RunOptions::kWavefront ||
        (opt.tracer == RunOptions::kAuto && simd_level_supported() == SimdLevel::Avx512);
    std::atomic<std::uint64_t> nextChunk{0}, done{0};
    std::mutex doneMutex;
    std::condition_variable doneCv;
    auto worker = [&](int id) {
        // A tally on this thread's own stack and heap (no false sharing of the per-ray counters
        // between threads), handed over at the end.
        Tally t = std::move(local[size_t(id)]);
        for (std::uint64_t ch = nextChunk++; ch < chunks; ch = nextChunk++) {
            const std::uint64_t n = std::min(kChunkRays, opt.rays - ch * kChunkRays);
            if (wavefront) {
                trace_chunk(sheet, wi, e1, e2, opt.incidence_cone, grids, opt.seed, ch, n, t);
            } else {
                Rng rng(opt.seed, ch);
                for (std::uint64_t r = 0; r < n; ++r) {
                    dvec3 w = wi;
                    if (opt.incidence_cone > 0)
                        w = sample_cone(wi, e1, e2, opt.incidence_cone, rng);
                    tally_path(trace_path(sheet, w, rng), grids, t);
                }
                t.rays += n;
            }
            if (done.fetch_add(n) + n == opt.rays) {
                // The last rays: wake the progress loop at once (not at its next tick).
                std::lock_guard<std::mutex> lock(doneMutex);
                doneCv.notify_all();
            }
        }
        local[size_t(id)] = std::move(t);
    };
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (int i = 0; i < run.threads; ++i)
        pool.emplace_back(worker, i);
    if (opt.progress) {
        std::unique_lock<std::mutex> lock(doneMutex);
        while (done.load() < opt.rays) {
            opt.progress(done.load(), opt.rays);
            doneCv.wait_for(lock, std::chrono::milliseconds(100),
                            [&] { return done.load() >= opt.rays; });
        }
        opt.progress(opt.rays, opt.rays);
    }
    for (std::thread& th : pool)
        th.join();
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run.tally.counts.resize(grids.size());
    for (size_t g = 0; g < grids.size(); ++g)
        run.tally.counts[g].assign(size_t(grids[g].cells()) * kChannels, 0);
    for (const Tally& t : local)
        run.tally.add(t);
    return run;
}

// ---- Estimates and analytic integrals
// ----------------------------------------------------------------

Estimate fraction(std::uint64_t count, std::uint64_t n) {
    Estimate e;
    if (n == 0) return e;
    const double p = double(count) / double(n);
    e.value = p;
    e.se = std::sqrt(std::max(0.0, p * (1.0 - p)) / double(n));
    return e;
}

Estimate cell_brdf(const Tally& t, int grid, int cell, int channel, double projected) {
    Estimate e;
    if (!(projected > 0) || t.rays == 0) return e;
    const std::uint64_t c = t.counts[size_t(grid)][size_t(cell) * kChannels + size_t(channel)];
    const Estimate fr = fraction(c, t.rays);
    e.value = fr.value / projected;
    e.se = fr.se / projected;
    return e;
}

CellIntegrals integrate_cells(const Grid& g, int k, const CellFunction& f,
                              const std::vector<Feature>& features, int minS, int maxS,
                              int threads) {
    CellIntegrals out;
    out.k = k;
    const int n = g.cells();
    out.projected.assign(size_t(n), 0.0);
    out.param_area.assign(size_t(n), 0.0);
    out.values.assign(size_t(n) * size_t(k), 0.0);
    const double dx = (g.x1 - g.x0) / g.nx, dy = (g.y1 - g.y0) / g.ny;
    parallel_for(size_t(n), threads, [&](size_t cellIndex) {
        const int cell = int(cellIndex);
        const int i = cell % g.nx, j = cell / g.nx;
        const double cx0 = g.x0 + i * dx, cy0 = g.y0 + j * dy;
        // The cell's angular size: the widest angle from its centre to a corner or edge
        // midpoint (the cone: its diameter).
        double jac;
        const dvec3 centre = g.cell_centre(cell);
        double radius = 0;
        if (g.kind == Grid::kCone) {
            radius = g.x1;
        } else {
            for (int a = 0; a <= 2; ++a)
                for (int b = 0; b <= 2; ++b)
                    radius = std::max(radius,
                                      angle_between(centre, g.direction(cx0 + 0.5 * a * dx,
                                                                        cy0 + 0.5 * b * dy, jac)));
        }
        int s = minS;
        for (const Feature& ft : features) {
            const double dist = angle_between(centre, ft.dir);
            if (dist < radius + 6.0 * ft.width)
                s = std::max(s, int(std::ceil(3.0 * 2.0 * radius / ft.width)));
        }
        s = std::min(s, maxS);
        std::vector<double> vals(static_cast<size_t>(k), 0.0);
        double proj = 0, area = 0;
        std::vector<double> acc(size_t(k), 0.0);
        const double sx = dx / s, sy = dy / s;
        for (int a = 0; a < s; ++a) {
            for (int b = 0; b < s; ++b) {
                const double x = cx0 + (a + 0.5) * sx, y = cy0 + (b + 0.5) * sy;
                const dvec3 w = g.direction(x, y, jac);
                if (!(w.z > 0)) continue;
                const double weight = (g.kind == Grid::kDisk ? kPi / 4 : w.z * jac) * sx * sy;
                proj += weight;
                area += sx * sy;
                if (k > 0) {
                    f(w, vals.data());
                    for (int q = 0; q < k; ++q)
                        acc[size_t(q)] += weight * vals[size_t(q)];
                }
            }
        }
        out.projected[size_t(cell)] = proj;
        out.param_area[size_t(cell)] = area;
        for (int q = 0; q < k; ++q)
            out.values[size_t(cell) * size_t(k) + size_t(q)] = acc[size_t(q)];
    });
    return out;
}

CellFunction model_function(const Params& params, const dvec3& wi) {
    const f64::rp_material m = prepare_material(sanitize(params));
    f64::rp_incident s;
    f64::rp_incident_setup(m, wi, s);
    return model_function(m, s, wi);
}

CellFunction model_function(const f64::rp_material& m, const f64::rp_incident& s, const dvec3& wi) {
    return [m, s, wi](const dvec3& wo, double* out) {
        out[0] = out[1] = out[2] = 0;
        if (!(wo.z >= f64::RP_MIN_COS) || !(wi.z >= f64::RP_MIN_COS)) return;
        f64::rp_lobes r;
        f64::rp_eval_lobes(m, s, wi, wo, r);
        out[0] = r.surface.x;
        out[1] = r.retro.x;
        out[2] = r.diffuse.x;
    };
}

LobeFit fit_lobe(const Grid& g, const std::vector<double>& density, const std::vector<double>& w,
                 const std::vector<char>& use) {
    LobeFit fit;
    // Normal equations of the 5-parameter linear model in (1, x, y, x^2, y^2).
    double ata[5][5] = {}, atb[5] = {};
    const double dx = (g.x1 - g.x0) / g.nx, dy = (g.y1 - g.y0) / g.ny;
    int used = 0;
    for (int cell = 0; cell < g.cells(); ++cell) {
        if (!use[size_t(cell)] || !(density[size_t(cell)] > 0) || !(w[size_t(cell)] > 0)) continue;
        const double x = g.x0 + (cell % g.nx + 0.5) * dx, y = g.y0 + (cell / g.nx + 0.5) * dy;
        const double row[5] = {1.0, x, y, x * x, y * y};
        const double v = std::log(density[size_t(cell)]);
        for (int a = 0; a < 5; ++a) {
            atb[a] += w[size_t(cell)] * row[a] * v;
            for (int b = 0; b < 5; ++b)
                ata[a][b] += w[size_t(cell)] * row[a] * row[b];
        }
        ++used;
    }
    fit.cells = used;
    if (used < 8) return fit;
    // The inverse of the normal matrix (its diagonal gives the coefficients' variances).
    double m[25], identity[25] = {}, inv[5][5];
    for (int a = 0; a < 5; ++a) {
        identity[a * 5 + a] = 1.0;
        for (int b = 0; b < 5; ++b)
            m[a * 5 + b] = ata[a][b];
    }
    if (!solve_linear(5, 5, m, identity, &inv[0][0])) return fit;
    double coef[5] = {};
    for (int a = 0; a < 5; ++a)
        for (int b = 0; b < 5; ++b)
            coef[a] += inv[a][b] * atb[b];
    // Reduced chi-square of the weighted fit.
    double chi2 = 0;
    for (int cell = 0; cell < g.cells(); ++cell) {
        if (!use[size_t(cell)] || !(density[size_t(cell)] > 0) || !(w[size_t(cell)] > 0)) continue;
        const double x = g.x0 + (cell % g.nx + 0.5) * dx, y = g.y0 + (cell / g.nx + 0.5) * dy;
        const double model =
            coef[0] + coef[1] * x + coef[2] * y + coef[3] * x * x + coef[4] * y * y;
        const double r = std::log(density[size_t(cell)]) - model;
        chi2 += w[size_t(cell)] * r * r;
    }
    fit.chi2_reduced = chi2 / std::max(1, used - 5);
    const double scale = std::max(1.0, fit.chi2_reduced);
    if (!(coef[3] < 0) || !(coef[4] < 0)) return fit;
    fit.ax = 1.0 / std::sqrt(-coef[3]);
    fit.ay = 1.0 / std::sqrt(-coef[4]);
    fit.se_ax = 0.5 * fit.ax * fit.ax * fit.ax * std::sqrt(inv[3][3] * scale);
    fit.se_ay = 0.5 * fit.ay * fit.ay * fit.ay * std::sqrt(inv[4][4] * scale);
    fit.mx = -coef[1] / (2 * coef[3]);
    fit.my = -coef[2] / (2 * coef[4]);
    fit.ok = true;
    return fit;
}

} // namespace sim
} // namespace retroprism
