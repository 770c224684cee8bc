// tracing.h: the pieces of a light path that the simulator's two tracers share: the scalar one of
// microgeometry.cpp (trace_path, one ray at a time) and the wavefront of wavefront.cpp (many rays
// in SIMD lanes, which `simulate` runs). Each piece is a function of its random draws, written
// once, inline, with IEEE double arithmetic only, so that a lane computes the same bits in a
// vector register as in a scalar one; their loops of fixed length are unrolled (`#pragma GCC
// unroll`) and their table reads unconditional, so that the vectoriser sees one straight body.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "batch.h"
#include "microgeometry.h"
#include "variates.h"

namespace retroprism {
namespace sim {
namespace tracing {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInvSqrtPi = 0.56418958354775628695;
constexpr double kSqrtPi = 1.77245385090551602730;
constexpr double kSqrt2Over3 = 0.81649658092772603273;
constexpr double kInvSqrt3 = 0.57735026918962576451;
constexpr double kInvSqrt2 = 0.70710678118654752440;
constexpr double kSin120 = 0.86602540378443864676;

// smith_lambda with Lambda from the table of sim/variates.h (relative error below 1e-10);
// Lambda = 0 where a = |w.z| / (alpha |w.xy|) > kLambdaCut (within 48 degrees of the normal for
// alpha = 0.1). From w's z, s2 = |w.xy|^2 and rxy = |w.xy|, or from w.
inline double walk_lambda(double z, double s2, double rxy, double alpha) {
    const bool steep = !(z * z < (kLambdaCut * kLambdaCut) * (alpha * alpha) * s2);
    // a = q / p and 1 / (2 a) = p / (2 q), p = alpha |w.xy|, q = |w.z|, over one division.
    const double p = alpha * rxy, q = std::abs(z), r = 1.0 / (p * q);
    const double a = q > 0 ? q * q * r : 0.0;
    const double g = beckmann_lambda_g(steep ? 2.0 * kLambdaCut : a);
    const double l = steep ? 0.0 : g * (0.5 * p * p * r);
    return z > 0 ? l : -1.0 - l;
}
inline double walk_lambda(const dvec3& w, double alpha) {
    const double s2 = w.x * w.x + w.y * w.y;
    return walk_lambda(w.z, s2, std::sqrt(s2), alpha);
}

// ---- The depth seen from the other side: -log(1 - exp(-l)) -----------------------------------
// The walk keeps the depth l = -log C(h) of its height (sim/microgeometry.cpp); from the other
// side of the microsurface the same height has depth -log(1 - exp(-l)). Evaluated with the
// arithmetic operations alone (no library call, whose vector and scalar variants may differ in
// the last bits): exp(-l) = 2^-n (1 + expm1(r)) by argument reduction, l = n ln2 - r with
// |r| <= ln2 / 2, and expm1(r) by its power series; 1 - exp(-l) is -expm1(r) itself where n = 0,
// else log1p(-exp(-l)) is formed with its rounding error corrected; the logarithm by the series
// of atanh. Within 5.3e-16 relative of the exact value (tests/sim/test_wavefront.cpp against long
// double); +inf at l = 0 (above every point, below every point from the other side).
constexpr double kLn2Hi = 6.93147180369123816490e-01; // 32 significant bits: k kLn2Hi is exact
constexpr double kLn2Lo = 1.90821492927058770002e-10;

inline double power_of_two(std::int64_t n) { // 2^n, -1022 <= n <= 1023
    return __builtin_bit_cast(double, std::uint64_t(n + 1023) << 52);
}

// log(q) + t / d for 0 <= q <= 1 (-inf at q = 0) and d > 0: the logarithm's series needs
// (m - 1) / (m + 1), and one division gives both quotients.
inline double log_unit_plus(double q, double t, double d) {
    const bool tiny = q < 0x1p-1000; // subnormal or near it: scaled up first
    const double qs = tiny ? q * 0x1p200 : q;
    const std::uint64_t bits = __builtin_bit_cast(std::uint64_t, qs);
    // 64-bit integers throughout: vectorised with doubles, 8 lanes to a vector in both.
    std::int64_t e = std::int64_t((bits >> 52) & 0x7ff) - 1023 - (tiny ? 200 : 0);
    double m = __builtin_bit_cast(double, (bits & 0x000fffffffffffffull) | 0x3ff0000000000000ull);
    const bool high = m > 1.41421356237309504880;
    m = high ? 0.5 * m : m; // [sqrt(1/2), sqrt2]
    e += high ? 1 : 0;
    const double r = 1.0 / ((m + 1.0) * d);
    const double s = (m - 1.0) * d * r, s2 = s * s; // |s| <= 0.1716, s2 <= 0.02944
    double p = 1.0 / 21; // sum s2^k / (2k + 1), k <= 10 (the next term below 2e-18)
#pragma GCC unroll 32
    for (int k = 9; k >= 0; --k)
        p = p * s2 + 1.0 / (2 * k + 1);
    const double ed = double(e);
    const double log = ed * kLn2Hi + (ed * kLn2Lo + 2.0 * s * p);
    return (q > 0 ? log : -HUGE_VAL) + t * (m + 1.0) * r;
}

inline double depth_flip(double l) {
    // 1 / (k + 1)! for expm1(r) = r sum r^k / (k + 1)!, to r^14 / 14! (the next term below
    // 2e-18 |r|).
    constexpr double kInvFact1[14] = {1.0,
                                      1.0 / 2,
                                      1.0 / 6,
                                      1.0 / 24,
                                      1.0 / 120,
                                      1.0 / 720,
                                      1.0 / 5040,
                                      1.0 / 40320,
                                      1.0 / 362880,
                                      1.0 / 3628800,
                                      1.0 / 39916800,
                                      1.0 / 479001600,
                                      1.0 / 6227020800.0,
                                      1.0 / 87178291200.0};
    const double lc = l < 745.2 ? l : 745.2;
    const std::int64_t n = std::int64_t(lc * 1.44269504088896340736 + 0.5);
    const double nd = double(n);
    const double r = (nd * kLn2Hi - lc) + nd * kLn2Lo; // -l + n ln2: -l exactly where n = 0
    double sum = kInvFact1[13];
#pragma GCC unroll 32
    for (int k = 12; k >= 0; --k)
        sum = sum * r + kInvFact1[k];
    const double em1 = r * sum;       // expm1(r)
    const std::int64_t half = n >> 1; // n >= 0
    // exp(-l), scaled in two steps (2^-n alone underflows for n > 1074).
    const double y = l < 745.2 ? (1.0 + em1) * power_of_two(-half) * power_of_two(half - n) : 0.0;
    const double u = 1.0 - y; // log1p(-y) = log(u) + ((1 - u) - y) / u
    // Where n = 0 (l < ln2 / 2), 1 - exp(-l) = -expm1(-l) without cancellation. One logarithm,
    // of the arguments of either case (a vector loop computes what it selects).
    const bool near = n == 0;
    return -log_unit_plus(near ? -em1 : u, near ? 0.0 : (1.0 - u) - y, near ? 1.0 : u);
}

// ---- Arctangents, for the tally's vectorised loops ---------------------------------------------
// atan(k / 8), k = 0 .. 8, rounded from 50 digits (at namespace scope: read by a gather in
// vector loops).
inline constexpr double kAtanEighths[9] = {0.0,
                                           0.12435499454676143503,
                                           0.24497866312686415417,
                                           0.35877067027057222040,
                                           0.46364760900080611621,
                                           0.55859931534356243597,
                                           0.64350110879328438680,
                                           0.71882999962162450542,
                                           0.78539816339744830962};

// atan(z) for |z| <= 1 with the arithmetic operations alone: atan(|z|) = atan(c) + atan(t) with
// c = k / 8 the nearest eighth of |z| and t = (|z| - c) / (1 + |z| c), |t| <= 1/16, atan(t) by
// its series to t^15 / 15 (the next term below 1e-19 |t|), atan(c) from the table. Within
// two ulps of libm's atan (tests/sim/test_wavefront.cpp).
inline double atan_unit(double z) {
    const double a = std::abs(z);
    const std::int64_t k = std::int64_t(a * 8.0 + 0.5); // 64 bits wide: a gather's index
    const double c = double(k) * 0.125;
    const double t = (a - c) / (1.0 + a * c), t2 = t * t;
    double p = -1.0 / 15; // sum (-1)^m t^2m / (2m + 1), m <= 7
#pragma GCC unroll 32
    for (int m = 6; m >= 0; --m)
        p = p * t2 + (m % 2 == 0 ? 1.0 : -1.0) / (2 * m + 1);
    const double r = kAtanEighths[k] + t * p;
    return z < 0 ? -r : r;
}

// atan2(y, x) in [-pi, pi] by atan_unit of the smaller magnitude over the larger (0 where both
// are 0); within three ulps of libm's atan2 (tests/sim/test_wavefront.cpp).
inline double atan2_of(double y, double x) {
    const double ay = std::abs(y), ax = std::abs(x);
    const bool steep = ay > ax;
    const double big = steep ? ay : ax;
    const double r0 = atan_unit((steep ? ax : ay) / (big > 0 ? big : 1.0)); // [0, pi/4]
    const double r1 = steep ? 0.5 * kPi - r0 : r0;                          // [0, pi/2]
    const double r = x < 0 ? kPi - r1 : r1;
    return y < 0 ? -r : r;
}

// Refraction of wIn (pointing away from the surface on the incident side, wIn.m = c > 0) at
// the microfacet m into the medium of relative index e = n_t / n_i, given as 1 / e (no total
// internal reflection: the Fresnel choice has already excluded it).
inline dvec3 refract_dir(const dvec3& wIn, const dvec3& m, double c, double invE) {
    const double cos2T = std::max(0.0, 1.0 - (1.0 - c * c) * (invE * invE));
    return glm::normalize(m * (c * invE - std::sqrt(cos2T)) - wIn * invE);
}

// (cos chi, sin chi) for chi = u pi / 3 in [0, 60) degrees, u in [0, 1): Taylor polynomials of
// cos and sin of x = chi - 30 degrees (|x| <= pi / 6; the first terms left out are below 5e-17),
// turned by 30 degrees: within 4e-16 of cos and sin (measured on 1e6 points), no branch and no
// rejection loop.
inline void sixth_turn(double u, double& c, double& s) {
    // 1 / (2k + 1)! and 1 / (2k)! with their signs.
    constexpr double kSin[7] = {1.0,          -1.0 / 6,        1.0 / 120,         -1.0 / 5040,
                                1.0 / 362880, -1.0 / 39916800, 1.0 / 6227020800.0};
    constexpr double kCos[8] = {
        1.0,         -0.5,           1.0 / 24,          -1.0 / 720,
        1.0 / 40320, -1.0 / 3628800, 1.0 / 479001600.0, -1.0 / 87178291200.0};
    const double x = (u - 0.5) * (kPi / 3.0), x2 = x * x;
    double sinX = kSin[6], cosX = kCos[7];
#pragma GCC unroll 32
    for (int k = 5; k >= 0; --k)
        sinX = sinX * x2 + kSin[k];
#pragma GCC unroll 32
    for (int k = 6; k >= 0; --k)
        cosX = cosX * x2 + kCos[k];
    sinX *= x;
    c = kSin120 * cosX - 0.5 * sinX; // cos(30 + x)
    s = 0.5 * cosX + kSin120 * sinX; // sin(30 + x)
}

// b_k = d.e_k of the paper's cube for a uniformly random orientation: psi uniform gives
// v_k.d = r cos(chi + 120 k degrees) with chi = psi - azimuth(d) uniform, and chi uniform in
// [0, 60) degrees gives the same outcomes in distribution (a turn of 120 degrees and the mirror
// image in the plane through d and the normal each map the prism onto itself with its faces
// permuted, under which the uniform entry point and the trace are symmetric). u: the turn.
inline void averaged_cube_b(const dvec3& d, double u, double b[3]) {
    double cosChi, sinChi;
    sixth_turn(u, cosChi, sinChi);
    const double r = kSqrt2Over3 * std::sqrt(d.x * d.x + d.y * d.y), z = kInvSqrt3 * d.z;
    const double along = -0.5 * r * cosChi, across = kSin120 * r * sinChi;
    b[0] = r * cosChi + z;
    b[1] = along - across + z;
    b[2] = along + across + z;
}

// The internal Fresnel reflectance of the core (rp_fresnel_internal) at cosine c below the
// critical angle, as a fraction n / d over one denominator (no division, for vectorised code):
// with cos_t = sqrt(1 - eta^2 (1 - c^2)), ds = eta c + cos_t, dp = c + eta cos_t and
// X = eta^2 - c^2 (eta^2 + 1), F = (r_s^2 + r_p^2) / 2 = (eta^2 - 1)^2 (dp^4 + X^2 ds^4) /
// (2 ds^4 dp^4) (tests/sim/test_wavefront.cpp checks it against the core).
inline void internal_reflectance_terms(double c, double eta, double& n, double& d) {
    const double eta2 = eta * eta;
    const double cosT = std::sqrt(std::max(0.0, 1.0 - (1.0 - c * c) * eta2));
    const double ds = eta * c + cosT, dp = c + eta * cosT;
    const double ds2 = ds * ds, dp2 = dp * dp, ds4 = ds2 * ds2, dp4 = dp2 * dp2;
    const double x = eta2 - c * c * (eta2 + 1.0), e2m1 = (eta - 1.0) * (eta + 1.0);
    n = 0.5 * e2m1 * e2m1 * (dp4 + x * x * ds4);
    d = ds4 * dp4;
}

// The paper's cube corner met by a downward ray with b_k = d.e_k (e_k the faces' normals) at the
// uniform entry point of its aperture given by (u, v) in [0, 1)^2, its faces as the sheet's
// prism_reflection, eta and metal_reflectance say; `roulette()` gives the uniform of the faces'
// Russian roulette: drawn in advance when kDrawn (for vectorised code), else called only when one
// is needed.
template <bool kDrawn, class Roulette>
inline PrismOutcome cube_outcome(int prismReflection, double eta, double metalReflectance,
                                 const double b[3], double u, double v, Roulette roulette) {
    double a[3];
    // The entry point in the coordinates a_k = x.e_k (the solid is a_k >= 0, a1 + a2 + a3 <= 1;
    // the aperture a1 + a2 + a3 = 1), folded into the triangle when u + v > 1 without a branch on
    // the random point: u + (1 - 2u) is 1 - u exactly (u a multiple of 2^-53 in [0, 1)).
    const double fold = double(u + v > 1.0);
    a[0] = u + fold * (1.0 - 2.0 * u);
    a[1] = v + fold * (1.0 - 2.0 * v);
    a[2] = std::max(0.0, 1.0 - a[0] - a[1]);
    // The faces are the coordinate planes of the orthonormal frame e_k, and a reflection on face
    // k only flips b_k: unfolded, the path is the straight line a + t b, its point in the solid
    // (|a_k + t b_k|), and the ray leaves through the aperture when S(t) = sum |a_k + t b_k|,
    // convex, 1 at t = 0 and decreasing there (sum b_k = sqrt3 d.z < 0), is back at 1. So face
    // k is hit (once, at cosine -b_k) iff b_k < 0 and S(t_k) < 1 at t_k = a_k / -b_k: the
    // faces hit and their cosines follow without tracing them in order. Multiplied by
    // -b_k > 0, S(t_k) < 1 reads sum_j |a_j (-b_k) + a_k b_j| < -b_k (term k is 0): no
    // division, and no branch on the random entry point.
    std::int64_t reflections = 0; // 64 bits wide, as the doubles (vectorised code)
    bool hit[3];
#pragma GCC unroll 32
    for (int k = 0; k < 3; ++k) {
        const int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;
        const double sAt =
            std::abs(a[k] * b[i] - a[i] * b[k]) + std::abs(a[k] * b[j] - a[j] * b[k]);
        hit[k] = (b[k] < 0) & (sAt < -b[k]);
        reflections += std::int64_t(hit[k]);
    }
    // Each hit reflects independently with its probability (tir: the internal Fresnel
    // reflectance at its cosine; metallized: metal_reflectance), so the ray survives its hits
    // with the product of those probabilities: one Russian roulette on the product.
    if (prismReflection == f64::RP_PRISM_TIR) {
        // The hits below the critical angle ((1 - c^2) eta^2 < 1; above it total internal
        // reflection, reflectance 1): found without a branch per face, then one branch (on the
        // way down, rarely taken) to their Fresnel terms.
        bool partial[3];
        bool any = false;
        for (int k = 0; k < 3; ++k) {
            partial[k] = hit[k] & ((1.0 - b[k] * b[k]) * eta * eta < 1.0);
            any |= partial[k];
        }
        if constexpr (kDrawn) {
            // Vectorised code: every face's term, their product n / d, and both tests at once
            // (selects), without a division.
            double n = 1.0, d = 1.0;
#pragma GCC unroll 32
            for (int k = 0; k < 3; ++k) {
                double nk, dk;
                internal_reflectance_terms(-b[k], eta, nk, dk);
                n *= partial[k] ? nk : 1.0;
                d *= partial[k] ? dk : 1.0;
            }
            if ((n < d) & (roulette() * d >= n)) return kPrismTransmitted;
        } else if (any) {
            double keep = 1.0;
            for (int k = 0; k < 3; ++k)
                if (partial[k]) keep *= f64::rp_fresnel_internal(-b[k], eta);
            if (keep < 1.0 && roulette() >= keep) return kPrismTransmitted;
        }
    } else if (prismReflection == f64::RP_PRISM_METALLIZED && reflections > 0) {
        const double m = metalReflectance;
        const double keep = reflections == 1 ? m : reflections == 2 ? m * m : m * m * m;
        if (roulette() >= keep) return kPrismAbsorbed;
    }
    return reflections == 3 ? kPrismRetro : kPrismMiss;
}

// The light of a path inside the sheet, below the top surface, from `where` (the prisms, met
// along the downward direction d, or the substrate), event by event (prisms, the substrate and
// its re-emission), until it goes up to the top surface (true, with `up` its direction) or ends
// (false: absorbed, p.fate says by what; trapped when `event` reaches kMaxEvents). `event` counts
// the path's events, `visited` says that it reached the substrate; p's counters are updated.
enum class Below { kPrisms, kSubstrate };
bool below_surface(const Sheet& sheet, Below where, const dvec3& d, bool& visited, int& event,
                   Path& p, Rng& rng, dvec3& up);

// The end of a crossing c of the top surface (upward: from inside the sheet): an exit (true: p's
// fate, by what the path has visited, and its exit direction set), or the light goes on below
// the surface (false) from `where`: the prisms, or, for light reflected back by the surface after
// the substrate on the paper's way up, the substrate (internal reflections counted).
inline bool leaves_sheet(const Sheet& sheet, const Crossing& c, bool upward, bool visited, Path& p,
                         Below& where) {
    if (c.outside) {
        p.fate = !upward ? kFateSurface : visited ? kFateDiffuse : kFateRetro;
        p.wo = c.dir;
        if (!upward) p.surface_order = c.order;
        return true;
    }
    where = Below::kPrisms;
    if (upward) {
        ++p.internal_reflections;
        if (visited && !sheet.upward_through_prisms) where = Below::kSubstrate;
    }
    return false;
}

// One more event of a path (a prism, the substrate, an upward crossing): false when the path has
// had kMaxEvents already (trapped).
inline bool count_event(int& event) {
    if (event == kMaxEvents) return false;
    ++event;
    return true;
}

// A path after its crossing c of the top surface (upward: from inside the sheet): its exit (false,
// p.fate and p.wo set), or the light inside the sheet (below_surface) until it goes up again
// (true: the next crossing, from inside along `up`, counted as an event) or ends (false).
bool after_crossing(const Sheet& sheet, const Crossing& c, bool upward, bool& visited, int& event,
                    Path& p, Rng& rng, dvec3& up);

// One path in a tally: its fate and counters and, for an exit, its cell in each grid.
void tally_path(const Path& p, const std::vector<Grid>& grids, Tally& t);
// The cells of grid g (Grid::cell_of) of n directions (wx, wy, wz)[k] into cell[k], by a
// vectorised loop (sim/wavefront.cpp) for the instruction set `level` (the same cells from every
// one), the arctangents by atan_unit and atan2_of.
void grid_cells(const Grid& g, const double* wx, const double* wy, const double* wz, int n,
                std::int64_t* cell, SimdLevel level);
// An exit in cell `cell` (>= 0) of a grid's counts: its channel and, for a surface exit after one
// scattering event, kSurfaceSingle too.
inline void count_exit(std::uint64_t* counts, std::int64_t cell, int channel, bool single) {
    const std::size_t at = std::size_t(cell) * kChannels;
    counts[at + std::size_t(channel)] += 1;
    if (single) counts[at + kSurfaceSingle] += 1;
}
// tally_path's part without the grids: the path's fate and counters; returns the channel of an
// exit (single: a surface exit after one scattering event), -1 for a path that ended inside.
int tally_counters(const Path& p, Tally& t, bool& single);

// Slope x of a visible normal of the standard Beckmann surface seen from polar angle theta in
// (0, pi) (cosT, sinT), by inversion of its CDF at u in (0, 1) (microgeometry.cpp).
double visible_slope_x(double cosT, double sinT, double u);

// A direction in the cone of half-angle r about c (frame e1, e2), with density proportional to
// its cos(theta) (z component) (microgeometry.cpp).
dvec3 sample_cone(const dvec3& c, const dvec3& e1, const dvec3& e2, double r, Rng& rng);

// The n rays of chunk `chunk` of a run (wavefront.cpp), t.rays included: light from wi, or from
// the cone of half-angle `cone` about it (frame e1, e2) when cone > 0, tallied into t; its rounds
// compiled for `level` (at most the CPU's), whose choice changes nothing in the results.
void trace_chunk(const Sheet& sheet, const dvec3& wi, const dvec3& e1, const dvec3& e2, double cone,
                 const std::vector<Grid>& grids, std::uint64_t seed, std::uint64_t chunk,
                 std::uint64_t n, Tally& t, SimdLevel level = SimdLevel::Avx512);

} // namespace tracing
} // namespace sim
} // namespace retroprism
