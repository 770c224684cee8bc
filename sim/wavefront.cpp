// wavefront.cpp: the simulator's tracer for whole chunks of rays (tracing.h trace_chunk), its
// events those of trace_path (microgeometry.cpp) in two kinds of rounds, each one loop that GCC
// vectorises (`omp simd`, the branches of the path turned into selects), compiled for each
// instruction set and chosen at run time:
//  - the surface round advances each of kLanes rays in flight (a lane of arrays each, with its
//    own random stream) by one step of the top surface's random walk and the scattering it leads
//    to;
//  - the rays whose crossing took them into the sheet then go below the surface: a compact list
//    of them, each position with its own stream, advances by one step per round (a cube corner
//    on the way down; or the substrate, its re-emission and the cube corner on the way up) until
//    each has gone up to the top surface again or ended; the list closes up after every round.
// A rejection sampler that rejects leaves its ray where it was, to try again in the next round
// with fresh draws. The rare cases the loops leave out (a ziggurat draw outside its layer's
// rectangle, a facet seen from below the mean plane, a canted or imperfect cube) mark the ray,
// which the same step function, compiled for one ray, then completes with the same draws and the
// stream's generator. A finished path is tallied (its exit direction waits with others for a
// vectorised loop per grid that finds their cells) and its lane takes the chunk's next ray; at
// the chunk's end the lanes still in use close up. The result depends on the seed and the chunk
// alone, and the rounds use IEEE arithmetic without contraction or library calls: the same bits
// whatever instruction set runs them.
#include "tracing.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "batch.h"
#include "cube_corner.h"

namespace retroprism {
namespace sim {
namespace tracing {

namespace {

constexpr int kLanes = 256; // rays in flight
constexpr int kDraws = 5;   // 64-bit draws per lane or list position and round (round_draws)

enum Phase : std::int64_t {
    kIdle = 0, // no ray
    kWalk,     // next intersection with the top surface's microsurface, then its scattering
    kScatter,  // the scattering alone (its sampler rejected in the last round)
    kLeft,     // the crossing is over: the path leaves the sheet, or goes on below its surface
    kBelow,    // below the surface (in the below-surface list)
    kDone      // the path has its fate
};

// The lanes: the walk's state (direction, side, depth, scattering order, the crossing's
// direction), the phase, the path's counters (Path's, kept between crossings), the lane's
// generator, and the last round's draws (for the completion of a marked lane).
struct alignas(64) Lanes {
    double wx[kLanes], wy[kLanes], wz[kLanes]; // direction of travel
    double depth[kLanes];                      // depth l on side depthOutside
    std::int64_t outside[kLanes];              // the side the walk is on
    std::int64_t depthOutside[kLanes];
    std::int64_t order[kLanes];  // scattering events of this crossing
    std::int64_t upward[kLanes]; // the crossing is from inside the sheet
    std::int64_t phase[kLanes];
    std::int64_t marked[kLanes]; // for completion by one lane's step
    Path path[kLanes];           // counters (and fate and exit when done)
    bool visited[kLanes];        // the path reached the substrate
    int events[kLanes];
    std::uint64_t s0[kLanes], s1[kLanes], s2[kLanes], s3[kLanes];
    std::uint64_t draw[kDraws][kLanes];
};

// c ? a : b by components (a select of whole vectors would pick an address to load from).
inline dvec3 pick(bool c, const dvec3& a, const dvec3& b) {
    return dvec3(c ? a.x : b.x, c ? a.y : b.y, c ? a.z : b.z);
}

// Stands for the generator where the vector loop has none (its continuations never run).
struct NoRng {
    std::uint64_t next() { return 0; }
    double uniform() { return 0; }
    double uniform_open() { return 0.5; }
};

// One event of lane i with the round's draws D. kVector: the vector loop, which marks the lane
// and leaves its state as it was where the event needs more than D (see the file's comment);
// otherwise the completion of a marked lane, which draws what it needs more from rng.
template <bool kVector, class R>
inline __attribute__((always_inline)) void
step(Lanes& L, int i, const Sheet& sheet, std::uint64_t D0, std::uint64_t D1, std::uint64_t D2,
     std::uint64_t D3, std::uint64_t D4, R& rng) {
    const std::int64_t phase = L.phase[i];
    const dvec3 w(L.wx[i], L.wy[i], L.wz[i]);
    double depth = L.depth[i];
    std::int64_t outside = L.outside[i], depthOutside = L.depthOutside[i];
    std::int64_t order = L.order[i];
    bool mark = false;
    // The sheet's inputs read once, at the top (a read under a condition is a masked load, which
    // GCC does not vectorise for a scalar).
    const double alpha = sheet.alpha, eta = sheet.eta, invEta = 1.0 / eta;

    // ---- The walk's next intersection (microgeometry.cpp next_depth, the same steps)
    const bool walking = phase == kWalk;
    const dvec3 ws = pick(outside, w, -w); // in the frame of its side
    const bool grazing = std::abs(ws.z) < 1e-12;
    const double s2 = w.x * w.x + w.y * w.y, rxy = std::sqrt(s2); // the walk's and the view's
    const double lambda = walk_lambda(ws.z, s2, rxy, alpha);
    const bool rising = ws.z > 0;
    const bool alwaysLeaves = !grazing & rising & !(lambda > 0);
    const bool random = walking & !grazing & !alwaysLeaves;
    double ez;
    const bool eFirst = exponential_first_try(D0, ez);
    if constexpr (kVector) {
        mark |= random & !eFirst;
    } else if (random & !eFirst) {
        ez = exponential_variate_from(D0, rng);
    }
    const double flipped = depth_flip(depth);
    const double lc = depthOutside != outside ? flipped : depth;
    const bool leaves = alwaysLeaves | (random & rising & (ez >= lambda * lc));
    const double step = ez / lambda; // ez / -lambda = -step exactly
    const double deeper = lc + (lambda == -1.0 ? ez : -step);
    const double higher = std::max(0.0, lc - step);
    depth = random ? (rising ? higher : deeper) : depth;
    depthOutside = random ? outside : depthOutside;
    const bool hits = walking & !leaves;
    const bool trapped = hits & (order == kMaxWalkOrder);
    const bool left = walking & leaves;

    // ---- A visible microfacet and the Fresnel choice (microgeometry.cpp sample_visible_normal
    // and cross_top_surface)
    const bool scattering = (hits & !trapped) | (phase == kScatter);
    const dvec3 wIn = -w;
    const dvec3 v = pick(outside, wIn, -wIn); // the view, in the frame of its side
    const double cosS = v.z, sinS = alpha * rxy;
    double g1, g3, e3;
    const bool g1First = normal_first_try(D1, g1);
    const bool g3First = normal_first_try(D3, g3);
    const bool e3First = exponential_first_try(D3, e3);
    const bool alongNormal = sinS * sinS < 1e-24 * (cosS * cosS + sinS * sinS);
    const bool above = cosS > 0;
    const double wGauss = cosS * kSqrtPi;
    // The tail component when u >= wGauss / (wGauss + sinS / 2), without the division.
    const bool tail =
        !alongNormal & above & (uniform_pair_of(D2).u * (wGauss + 0.5 * sinS) >= wGauss);
    const bool needG3 = scattering & (alongNormal | (above & !tail));
    const bool needE3 = scattering & tail;
    const bool below = scattering & !alongNormal & !above;
    if constexpr (kVector) {
        mark |= (scattering & !g1First) | (needG3 & !g3First) | (needE3 & !e3First) | below;
    } else {
        if (scattering & !g1First) g1 = normal_variate_from(D1, rng);
        if (needG3 & !g3First) g3 = normal_variate_from(D3, rng);
        if (needE3 & !e3First) e3 = exponential_variate_from(D3, rng);
    }
    const double sy = kInvSqrt2 * g1, x = kInvSqrt2 * g3;
    const double rootE3 = std::sqrt(e3);
    double sx = tail ? -rootE3 : x;
    if (!kVector & below) { // constant-folded in the vector loop
        const double n = 1.0 / std::sqrt(cosS * cosS + sinS * sinS);
        sx = visible_slope_x(cosS * n, sinS * n, Rng::uniform_open_of(D3));
    }
    // Accepted when the tail component was drawn, x <= 0, or by the ratio p / q.
    const bool accepted =
        alongNormal | !above | tail | (x <= 0) | (uniform_pair_of(D2).v * cosS < cosS - x * sinS);
    const double inv = 1.0 / rxy;
    const double cosPhi = alongNormal ? 1.0 : v.x * inv, sinPhi = alongNormal ? 0.0 : v.y * inv;
    const double tx = alpha * (cosPhi * sx - sinPhi * sy);
    const double ty = alpha * (sinPhi * sx + cosPhi * sy);
    dvec3 m = glm::normalize(dvec3(-tx, -ty, 1.0));
    m = pick(outside, m, -m);
    const double c = std::max(glm::dot(wIn, m), 0.0);
    // The Fresnel reflectance at the facet for the relative index e of the side's crossing (the
    // core's, total internal reflection included); the reflected or refracted direction
    // a m + b wIn, unit up to rounding (m and wIn are unit), left unnormalised.
    const double e = outside ? eta : invEta, invE = outside ? invEta : eta;
    const double fr = f64::rp_fresnel_dielectric(c, e);
    const bool reflects = Rng::uniform_of(D4) < fr;
    const double cosT = std::sqrt(std::max(0.0, 1.0 - (1.0 - c * c) * (invE * invE)));
    const double ma = reflects ? 2.0 * c : c * invE - cosT, mb = reflects ? -1.0 : -invE;
    const dvec3 wScattered = ma * m + mb * wIn;
    const bool scattered = scattering & accepted;

    // ---- The next phase
    dvec3 wNext = w;
    std::int64_t nextPhase = phase;
    if (left) nextPhase = kLeft;
    if (trapped) nextPhase = kDone; // more than kMaxWalkOrder scattering events
    if (scattering) {
        wNext = pick(scattered, wScattered, w);
        outside = (scattered & !reflects) ? !outside : outside;
        order += scattered;
        nextPhase = scattered ? kWalk : kScatter;
    }

    // ---- Stores: a marked lane keeps its state for its completion (selects, not a branch, so
    // that the loop stores whole vectors).
    L.marked[i] = mark;
    L.wx[i] = mark ? w.x : wNext.x;
    L.wy[i] = mark ? w.y : wNext.y;
    L.wz[i] = mark ? w.z : wNext.z;
    L.depth[i] = mark ? L.depth[i] : depth;
    L.outside[i] = mark ? L.outside[i] : outside;
    L.depthOutside[i] = mark ? L.depthOutside[i] : depthOutside;
    L.order[i] = mark ? L.order[i] : order;
    L.phase[i] = mark ? phase : nextPhase;
}

// ---- Below the surface: cube corners, the substrate and its re-emission, one step per element
// and round (tracing.h below_surface, the same events and counters), over a compact list of the
// paths whose light is inside the sheet, each position of the list with its own generator. A step
// meets one cube corner at most: on the way down, or on the way up through the prisms right after
// the substrate's re-emission (so that a diffuse visit takes two steps, and every step computes
// one cube).
enum Where : std::int64_t {
    kDown = 0,    // a cube corner on the way down, along d
    kAtSubstrate, // absorbed, or re-emitted (and up through a cube corner)
    kEmitting,    // the re-emission alone (its sampler rejected in the last round)
    kGoesUp,      // up to the top surface along d
    kEnded        // absorbed or trapped (fate)
};

struct alignas(64) BelowList {
    double dx[kLanes], dy[kLanes], dz[kLanes];
    std::int64_t where[kLanes];
    std::int64_t lane[kLanes];
    std::int64_t visited[kLanes], events[kLanes], fate[kLanes];
    std::int64_t retro[kLanes], transmitted[kLanes], substrate[kLanes];
    std::int64_t marked[kLanes];
    std::uint64_t s0[kLanes], s1[kLanes], s2[kLanes], s3[kLanes];
    std::uint64_t draw[kDraws][kLanes];
};

template <bool kVector, class R>
inline __attribute__((always_inline)) void
below_step(BelowList& B, int j, const Sheet& sheet, bool averagedCube, std::uint64_t D0,
           std::uint64_t D1, std::uint64_t D2, std::uint64_t D3, std::uint64_t D4, R& rng) {
    const std::int64_t where = B.where[j];
    const dvec3 d(B.dx[j], B.dy[j], B.dz[j]);
    std::int64_t visited = B.visited[j], events = B.events[j], fate = B.fate[j];
    std::int64_t retro = B.retro[j], transmitted = B.transmitted[j], substrate = B.substrate[j];
    bool mark = false;
    const double eta = sheet.eta, kd = sheet.kd, metal = sheet.metal_reflectance;
    const int reflection = sheet.prism_reflection;
    const bool upThrough = sheet.upward_through_prisms;

    // A new event (the prisms on the way down, the substrate) is counted, or the path trapped.
    const bool counted = (where == kDown) | (where == kAtSubstrate);
    const bool trapped = counted & (events == kMaxEvents);
    events += counted & !trapped;

    // ---- The substrate: absorbed, or re-emitted by Malley's method (a uniform point of the unit
    // disk by rejection, lifted to the hemisphere)
    const bool atSubstrate = (where == kAtSubstrate) & !trapped;
    const bool absorbed = atSubstrate & (Rng::uniform_of(D3) >= kd);
    const bool emitting = (atSubstrate & !absorbed) | (where == kEmitting);
    const UniformPair disk = uniform_pair_of(D4); // a point of the square about the disk
    const double px = 2.0 * disk.u - 1.0, py = 2.0 * disk.v - 1.0;
    const double r2 = px * px + py * py;
    const bool emitted = emitting & (r2 < 1.0);
    const dvec3 up(px, py, std::sqrt(std::max(0.0, 1.0 - r2)));

    // ---- A cube corner: down along d, or the adjoint of the way up through the prisms (along
    // -up). The paper's cube at a random orientation in the loop (computed whatever the sheet, so
    // that nothing in the loop is read under a condition); any other cube in the completion.
    const bool down = (where == kDown) & !trapped, upTrace = emitted & upThrough;
    const dvec3 dd = pick(upTrace, -up, d);
    double b[3];
    const UniformPair turn = uniform_pair_of(D0); // the turn, the faces' roulette
    averaged_cube_b(dd, turn.u, b);
    const double roulette = turn.v;
    PrismOutcome outcome =
        cube_outcome<true>(reflection, eta, metal, b, Rng::uniform_of(D1), Rng::uniform_of(D2),
                           [roulette]() { return roulette; });
    dvec3 exit = -dd;
    if constexpr (kVector) {
        mark |= (!averagedCube) & (down | upTrace);
    } else if ((!averagedCube) & (down | upTrace)) {
        outcome = trace_prism(sheet, dd, rng, down ? &exit : nullptr);
    }

    // ---- What next
    std::int64_t next = where;
    dvec3 dNext = d;
    if (trapped) next = kEnded; // fate: trapped
    if (down) {
        if (outcome == kPrismRetro) {
            ++retro;
            dNext = exit;
            next = kGoesUp;
        } else if (outcome == kPrismAbsorbed) {
            fate = kFateAbsorbedFaces;
            next = kEnded;
        } else {
            transmitted += outcome == kPrismTransmitted;
            next = kAtSubstrate;
        }
    }
    if (atSubstrate) {
        visited = 1;
        ++substrate;
    }
    if (absorbed) {
        fate = kFateAbsorbedSubstrate;
        next = kEnded;
    }
    if (emitting) {
        next = kEmitting;
        if (emitted) {
            dNext = up;
            next = kGoesUp;
        }
    }
    if (upTrace) {
        if (outcome == kPrismRetro) { // back to the substrate
            next = kAtSubstrate;
        } else if (outcome == kPrismAbsorbed) {
            fate = kFateAbsorbedFaces;
            next = kEnded;
        } else {
            transmitted += outcome == kPrismTransmitted;
        }
    }

    // ---- Stores: a marked element keeps its state for its completion.
    B.marked[j] = mark;
    B.dx[j] = mark ? d.x : dNext.x;
    B.dy[j] = mark ? d.y : dNext.y;
    B.dz[j] = mark ? d.z : dNext.z;
    B.where[j] = mark ? where : next;
    B.visited[j] = mark ? B.visited[j] : visited;
    B.events[j] = mark ? B.events[j] : events;
    B.fate[j] = mark ? B.fate[j] : fate;
    B.retro[j] = mark ? B.retro[j] : retro;
    B.transmitted[j] = mark ? B.transmitted[j] : transmitted;
    B.substrate[j] = mark ? B.substrate[j] : substrate;
}

// The five draws of one round for position i of `A` (the lanes or the list below the surface):
// from its generator, kept for the completion of a marked position.
struct RoundDraws {
    std::uint64_t d0, d1, d2, d3, d4;
};
template <class A>
inline __attribute__((always_inline)) RoundDraws round_draws(A& a, int i) {
    std::uint64_t& s0 = a.s0[i];
    std::uint64_t& s1 = a.s1[i];
    std::uint64_t& s2 = a.s2[i];
    std::uint64_t& s3 = a.s3[i];
    const std::uint64_t d0 = Rng::xoshiro256ss(s0, s1, s2, s3);
    const std::uint64_t d1 = Rng::xoshiro256ss(s0, s1, s2, s3);
    const std::uint64_t d2 = Rng::xoshiro256ss(s0, s1, s2, s3);
    const std::uint64_t d3 = Rng::xoshiro256ss(s0, s1, s2, s3);
    const std::uint64_t d4 = Rng::xoshiro256ss(s0, s1, s2, s3);
    a.draw[0][i] = d0;
    a.draw[1][i] = d1;
    a.draw[2][i] = d2;
    a.draw[3][i] = d3;
    a.draw[4][i] = d4;
    return {d0, d1, d2, d3, d4};
}

inline __attribute__((always_inline)) void round_below(BelowList& B, int n, const Sheet& sheet,
                                                       bool averagedCube) {
    NoRng none;
#pragma omp simd
    for (int j = 0; j < n; ++j) {
        const RoundDraws D = round_draws(B, j);
        below_step<true>(B, j, sheet, averagedCube, D.d0, D.d1, D.d2, D.d3, D.d4, none);
    }
}

// One round of every lane, for one instruction set.
inline __attribute__((always_inline)) void round_of_lanes(Lanes& L, int n, const Sheet& sheet) {
    NoRng none;
#pragma omp simd
    for (int i = 0; i < n; ++i) {
        const RoundDraws D = round_draws(L, i);
        step<true>(L, i, sheet, D.d0, D.d1, D.d2, D.d3, D.d4, none);
    }
}

// ---- The tally's cells: each grid's cell of many exit directions in one vectorised loop
// (Grid::cell_of's arithmetic, its arctangents those of tracing.h), -1 outside the grid; cones
// are left to Grid::cell_of (kNoCell).
constexpr std::int64_t kNoCell = -2;

struct CellGrid {
    std::int64_t kind;
    dvec3 c, e1, e2;
    double x0, x1, y0, y1;
    double perX, perY;       // cells per unit of each parameter
    double xLastIn, yLastIn; // the largest parameters inside (the disk's outer edge)
    std::int64_t nx, ny;
};

CellGrid cell_grid(const Grid& g) {
    return {g.kind,
            g.c,
            g.e1,
            g.e2,
            g.x0,
            g.x1,
            g.y0,
            g.y1,
            g.nx / (g.x1 - g.x0),
            g.ny / (g.y1 - g.y0),
            std::nextafter(g.x1, g.x0),
            std::nextafter(g.y1, g.y0),
            g.nx,
            g.ny};
}

// The cell of parameters (x, y) where `inside`, else -1; the disk's outer edge (x or y = 1)
// belongs to its last cells.
inline std::int64_t cell_at(const CellGrid& g, double x, double y, bool inside, bool disk) {
    const bool inOpen = (x >= g.x0) & (x < g.x1) & (y >= g.y0) & (y < g.y1);
    const bool onEdge = disk & !inOpen & (x >= g.x0) & (x <= g.x1) & (y >= g.y0) & (y <= g.y1);
    const bool in = inside & (inOpen | onEdge);
    const double xLast = g.xLastIn, yLast = g.yLastIn; // read unconditionally (vector loops)
    const double xc = (onEdge & (x > xLast)) ? xLast : x;
    const double yc = (onEdge & (y > yLast)) ? yLast : y;
    const std::int64_t i = std::min(g.nx - 1, std::int64_t(in ? (xc - g.x0) * g.perX : 0.0));
    const std::int64_t j = std::min(g.ny - 1, std::int64_t(in ? (yc - g.y0) * g.perY : 0.0));
    return in ? j * g.nx + i : -1;
}

inline __attribute__((always_inline)) void cells_of(const CellGrid& g, const double* wx,
                                                    const double* wy, const double* wz, int n,
                                                    std::int64_t* cell) {
    switch (g.kind) {
    case Grid::kGnomonic:
#pragma omp simd
        for (int k = 0; k < n; ++k) {
            const dvec3 w(wx[k], wy[k], wz[k]);
            const double cp = glm::dot(w, g.c);
            const double q = cp > 0 ? cp : 1.0;
            cell[k] = cell_at(g, glm::dot(w, g.e1) / q, glm::dot(w, g.e2) / q, cp > 0, false);
        }
        break;
    case Grid::kDisk:
#pragma omp simd
        for (int k = 0; k < n; ++k) {
            // The concentric map's inverse (microgeometry.cpp disk_to_square): the sector by
            // comparison, its angle by the arctangent of a ratio in [-1, 1].
            const double x = wx[k], y = wy[k];
            const double r = std::sqrt(x * x + y * y);
            const bool wide = std::abs(x) > std::abs(y);
            const double num = wide ? y : x, den = wide ? x : y;
            const double t = r * atan_unit(num / (r > 0 ? den : 1.0)) * (4 / kPi);
            const bool positive = den > 0;
            const double u = wide ? r : t, v = wide ? t : r;
            const double sx = r > 0 ? (positive ? u : -u) : 0.0;
            const double sy = r > 0 ? (positive ? v : -v) : 0.0;
            cell[k] = cell_at(g, sx, sy, wz[k] >= 0, true);
        }
        break;
    case Grid::kStrip:
#pragma omp simd
        for (int k = 0; k < n; ++k) {
            const dvec3 w(wx[k], wy[k], wz[k]);
            const double t = glm::dot(w, g.e2);
            const bool out = ((g.y1 >= 0) & (t > g.y1)) | ((g.y0 <= 0) & (t < g.y0));
            const double tc = std::clamp(t, -1.0, 1.0);
            const double x = atan2_of(glm::dot(w, g.e1), glm::dot(w, g.c));
            const double y = atan2_of(tc, std::sqrt(std::max(0.0, 1.0 - tc * tc))); // asin
            cell[k] = cell_at(g, x, y, !out, false);
        }
        break;
    default:
        for (int k = 0; k < n; ++k)
            cell[k] = kNoCell;
    }
}

// The two rounds of one instruction set.
struct Rounds {
    void (*surface)(Lanes&, int, const Sheet&);
    void (*below)(BelowList&, int, const Sheet&, bool);
    void (*cells)(const CellGrid&, const double*, const double*, const double*, int, std::int64_t*);
};
#define RP_SIM_ROUNDS(NAME, ...)                                                                   \
    __VA_ARGS__ __attribute__((flatten, noinline)) void NAME##_surface(Lanes& L, int n,            \
                                                                       const Sheet& sheet) {       \
        round_of_lanes(L, n, sheet);                                                               \
    }                                                                                              \
    __VA_ARGS__ __attribute__((flatten, noinline)) void NAME##_below(                              \
        BelowList& B, int n, const Sheet& sheet, bool averagedCube) {                              \
        round_below(B, n, sheet, averagedCube);                                                    \
    }                                                                                              \
    __VA_ARGS__ __attribute__((flatten, noinline)) void NAME##_cells(                              \
        const CellGrid& g, const double* wx, const double* wy, const double* wz, int n,            \
        std::int64_t* cell) {                                                                      \
        cells_of(g, wx, wy, wz, n, cell);                                                          \
    }                                                                                              \
    const Rounds NAME = {NAME##_surface, NAME##_below, NAME##_cells};
RP_SIM_ROUNDS(rounds_baseline, )
RP_SIM_ROUNDS(rounds_avx2, RP_TARGET_AVX2)
RP_SIM_ROUNDS(rounds_avx512, RP_TARGET_AVX512)
#undef RP_SIM_ROUNDS

const Rounds& rounds(SimdLevel level) {
    switch (std::min(level, simd_level_supported())) {
    case SimdLevel::Avx512:
        return rounds_avx512;
    case SimdLevel::Avx2:
        return rounds_avx2;
    default:
        return rounds_baseline;
    }
}

// The cells of grid g of n directions (Grid::cell_of), by the vectorised loop of `run`.
void grid_cells(const Grid& g, const double* wx, const double* wy, const double* wz, int n,
                std::int64_t* cell, const Rounds& run) {
    run.cells(cell_grid(g), wx, wy, wz, n, cell);
    for (int k = 0; k < n; ++k)
        if (cell[k] == kNoCell) cell[k] = g.cell_of(dvec3(wx[k], wy[k], wz[k]));
}

// A new path's counters, field by field (an assignment of Path() goes through a temporary on the
// stack whose 16-byte reloads wait for its 8-byte stores).
inline void reset_path(Path& p) {
    p.fate = kFateTrapped;
    p.wo = dvec3(0.0);
    p.surface_order = 0;
    p.retroreflections = 0;
    p.internal_reflections = 0;
    p.substrate_hits = 0;
    p.face_transmissions = 0;
}

// A generator from a state held in four words, and back.
Rng rng_of(const std::uint64_t& s0, const std::uint64_t& s1, const std::uint64_t& s2,
           const std::uint64_t& s3) {
    const std::uint64_t s[4] = {s0, s1, s2, s3};
    return Rng::from_state(s);
}
void keep_state(const Rng& r, std::uint64_t& s0, std::uint64_t& s1, std::uint64_t& s2,
                std::uint64_t& s3) {
    std::uint64_t s[4];
    r.state(s);
    s0 = s[0];
    s1 = s[1];
    s2 = s[2];
    s3 = s[3];
}

// One chunk's rays through the rounds: the lanes, the list below the surface, and the work of
// one ray at a time between the rounds.
class Chunk {
  public:
    Chunk(const Sheet& sheet, const dvec3& wi, const dvec3& e1, const dvec3& e2, double cone,
          const std::vector<Grid>& grids, std::uint64_t seed, std::uint64_t chunk, std::uint64_t n,
          Tally& t, SimdLevel level)
        : sheet_(sheet), wi_(wi), e1_(e1), e2_(e2), cone_(cone), grids_(grids), n_(n), t_(t),
          run_(rounds(level)), rng_(seed, chunk),
          averagedCube_(sheet.era_mode == f64::RP_ERA_AVERAGED && sheet.cant_deg == 0.0 &&
                        sheet.dihedral_arcmin == 0.0 && sheet.dihedral_spread_arcmin == 0.0) {
        // Streams (seed, chunk + k 2^40), k = 1 .. kLanes for the lanes and kLanes + 1 ..
        // 2 kLanes for the positions of the list below the surface: disjoint from the chunks'
        // own (< 2^40).
        for (int i = 0; i < kLanes; ++i) {
            const std::uint64_t k = std::uint64_t(i) + 1;
            keep_state(Rng(seed, chunk + k * (std::uint64_t(1) << 40)), L_.s0[i], L_.s1[i],
                       L_.s2[i], L_.s3[i]);
            keep_state(Rng(seed, chunk + (k + kLanes) * (std::uint64_t(1) << 40)), B_.s0[i],
                       B_.s1[i], B_.s2[i], B_.s3[i]);
            L_.phase[i] = kIdle;
            L_.marked[i] = 0;
        }
    }

    void run() {
        while (lanes_ < kLanes && started_ < n_)
            start(lanes_++);
        while (lanes_ > 0) {
            run_.surface(L_, lanes_, sheet_);
            nb_ = nd_ = 0;
            after_surface_round();
            while (nb_ > 0)
                below_round();
            // Finished paths are tallied, and their lanes take the next rays.
            for (int k = 0; k < nd_; ++k) {
                const int i = done_[k];
                tally(L_.path[i]);
                if (started_ < n_)
                    start(i);
                else
                    L_.phase[i] = kIdle;
            }
            if (started_ == n_ && nd_ > 0) close_up_lanes();
        }
        tally_exits();
        t_.rays += n_;
    }

  private:
    // A finished path's fate and counters, and its exit (if any) among those whose cells the
    // next tally_exits finds.
    void tally(const Path& p) {
        bool single;
        const int channel = tally_counters(p, t_, single);
        if (channel < 0) return;
        if (ne_ == kLanes) tally_exits();
        exitX_[ne_] = p.wo.x;
        exitY_[ne_] = p.wo.y;
        exitZ_[ne_] = p.wo.z;
        channel_[ne_] = channel;
        single_[ne_] = single;
        ++ne_;
    }

    // The pending exits in each grid's cells (tally_path's counts).
    void tally_exits() {
        for (size_t g = 0; g < grids_.size(); ++g) {
            grid_cells(grids_[g], exitX_, exitY_, exitZ_, ne_, cell_, run_);
            std::uint64_t* counts = t_.counts[g].data();
            // The exits inside the grid, found without a branch per exit (inside or not is a
            // coin toss to a branch predictor), then counted.
            int inside = 0;
            for (int k = 0; k < ne_; ++k) {
                inside_[inside] = k;
                inside += int(cell_[k] >= 0);
            }
            for (int q = 0; q < inside; ++q) {
                const int k = inside_[q];
                count_exit(counts, cell_[k], channel_[k], single_[k]);
            }
        }
        ne_ = 0;
    }

    // A lane takes the chunk's next ray.
    void start(int i) {
        ++started_;
        const dvec3 w = cone_ > 0 ? sample_cone(wi_, e1_, e2_, cone_, rng_) : wi_;
        L_.wx[i] = -w.x;
        L_.wy[i] = -w.y;
        L_.wz[i] = -w.z;
        L_.depth[i] = 0.0;
        L_.outside[i] = L_.depthOutside[i] = 1;
        L_.order[i] = L_.upward[i] = 0;
        L_.phase[i] = kWalk;
        reset_path(L_.path[i]);
        L_.visited[i] = false;
        L_.events[i] = 0;
    }

    // The lanes the surface round left to this loop: the marked ones, completed one lane at a
    // time with their own generators; finished crossings: exits, or the light goes below the
    // surface. Lists found without a branch per lane (whether a crossing is over, and how, is a
    // coin toss to a branch predictor), each then handled in order.
    void after_surface_round() {
        int na = 0;
        for (int i = 0; i < lanes_; ++i) {
            attention_[na] = i;
            na += int((L_.phase[i] >= kLeft) | (L_.marked[i] != 0));
        }
        int nx = 0, nb = 0;
        for (int k = 0; k < na; ++k) {
            const int i = attention_[k];
            if (L_.marked[i]) {
                Rng r = rng_of(L_.s0[i], L_.s1[i], L_.s2[i], L_.s3[i]);
                step<false>(L_, i, sheet_, L_.draw[0][i], L_.draw[1][i], L_.draw[2][i],
                            L_.draw[3][i], L_.draw[4][i], r);
                keep_state(r, L_.s0[i], L_.s1[i], L_.s2[i], L_.s3[i]);
                L_.marked[i] = 0;
            }
            // Done (trapped in the crossing: Path's fate as it starts) or exiting; going below.
            const std::int64_t phase = L_.phase[i];
            const bool out = L_.outside[i] != 0;
            exiting_[nx] = i;
            nx += int((phase == kDone) | ((phase == kLeft) & out));
            going_[nb] = i;
            nb += int((phase == kLeft) & !out);
        }
        for (int k = 0; k < nx; ++k) {
            const int i = exiting_[k];
            if (L_.phase[i] == kDone)
                done_[nd_++] = i;
            else
                leave_crossing(i);
        }
        for (int k = 0; k < nb; ++k)
            leave_crossing(going_[k]);
    }

    // The exit of lane i's path, or its light into the list below (leaves_sheet).
    void leave_crossing(int i) {
        Path& p = L_.path[i];
        Crossing c;
        c.dir = dvec3(L_.wx[i], L_.wy[i], L_.wz[i]);
        c.outside = L_.outside[i] != 0;
        c.order = int(L_.order[i]);
        Below below;
        if (leaves_sheet(sheet_, c, L_.upward[i] != 0, L_.visited[i], p, below)) {
            L_.phase[i] = kDone;
            done_[nd_++] = i;
            return;
        }
        const Where where = below == Below::kPrisms ? kDown : kAtSubstrate;
        const int j = nb_++;
        B_.dx[j] = L_.wx[i];
        B_.dy[j] = L_.wy[i];
        B_.dz[j] = L_.wz[i];
        B_.where[j] = where;
        B_.lane[j] = i;
        B_.visited[j] = L_.visited[i];
        B_.events[j] = L_.events[i];
        B_.fate[j] = kFateTrapped;
        B_.retro[j] = p.retroreflections;
        B_.transmitted[j] = p.face_transmissions;
        B_.substrate[j] = p.substrate_hits;
        B_.marked[j] = 0;
        L_.phase[i] = kBelow;
    }

    // One round below the surface; the elements that have gone up or ended (found without a
    // branch per element) go back to their lanes and the list closes up.
    void below_round() {
        run_.below(B_, nb_, sheet_, averagedCube_);
        if (!averagedCube_) { // the other cubes: in the marked elements' completions
            for (int j = 0; j < nb_; ++j) {
                if (!B_.marked[j]) continue;
                Rng r = rng_of(B_.s0[j], B_.s1[j], B_.s2[j], B_.s3[j]);
                below_step<false>(B_, j, sheet_, averagedCube_, B_.draw[0][j], B_.draw[1][j],
                                  B_.draw[2][j], B_.draw[3][j], B_.draw[4][j], r);
                keep_state(r, B_.s0[j], B_.s1[j], B_.s2[j], B_.s3[j]);
            }
        }
        int nf = 0;
        for (int j = 0; j < nb_; ++j) {
            finished_[nf] = j;
            nf += int(B_.where[j] >= kGoesUp);
        }
        for (int k = 0; k < nf; ++k)
            back_to_lane(finished_[k]);
        close_up_list(nb_ - nf);
    }

    // Element j back to its lane: up to the top surface (an event), or done.
    void back_to_lane(int j) {
        const int i = int(B_.lane[j]);
        Path& p = L_.path[i];
        p.retroreflections = int(B_.retro[j]);
        p.face_transmissions = int(B_.transmitted[j]);
        p.substrate_hits = int(B_.substrate[j]);
        p.fate = int(B_.fate[j]);
        L_.visited[i] = B_.visited[j] != 0;
        L_.events[i] = int(B_.events[j]);
        if (B_.where[j] == kGoesUp && count_event(L_.events[i])) { // the upward crossing
            L_.wx[i] = B_.dx[j];
            L_.wy[i] = B_.dy[j];
            L_.wz[i] = B_.dz[j];
            L_.depth[i] = 0.0;
            L_.outside[i] = L_.depthOutside[i] = 0;
            L_.order[i] = 0;
            L_.upward[i] = 1;
            L_.phase[i] = kWalk;
        } else {
            L_.phase[i] = kDone; // p.fate says how (trapped at the event limit)
            done_[nd_++] = i;
        }
    }

    // The elements still below fill the front of the list: those beyond its new end move into
    // the finished ones' places before it (each position keeps its generator).
    void close_up_list(int kept) {
        int holes = 0, movers = 0;
        for (int j = 0; j < nb_; ++j) {
            const bool gone = B_.where[j] >= kGoesUp;
            hole_[holes] = j;
            holes += int(gone & (j < kept));
            mover_[movers] = j;
            movers += int(!gone & (j >= kept));
        }
        for (int k = 0; k < movers; ++k) {
            const int to = hole_[k], from = mover_[k];
            B_.dx[to] = B_.dx[from];
            B_.dy[to] = B_.dy[from];
            B_.dz[to] = B_.dz[from];
            B_.where[to] = B_.where[from];
            B_.lane[to] = B_.lane[from];
            B_.visited[to] = B_.visited[from];
            B_.events[to] = B_.events[from];
            B_.fate[to] = B_.fate[from];
            B_.retro[to] = B_.retro[from];
            B_.transmitted[to] = B_.transmitted[from];
            B_.substrate[to] = B_.substrate[from];
        }
        nb_ = kept;
    }

    // The chunk's last rays: the lanes still in use move to the front, so that the rounds run
    // over them alone (each position keeps its generator).
    void close_up_lanes() {
        int kept = 0;
        for (int i = 0; i < lanes_; ++i) {
            if (L_.phase[i] == kIdle) continue;
            if (kept != i) {
                L_.wx[kept] = L_.wx[i];
                L_.wy[kept] = L_.wy[i];
                L_.wz[kept] = L_.wz[i];
                L_.depth[kept] = L_.depth[i];
                L_.outside[kept] = L_.outside[i];
                L_.depthOutside[kept] = L_.depthOutside[i];
                L_.order[kept] = L_.order[i];
                L_.upward[kept] = L_.upward[i];
                L_.phase[kept] = L_.phase[i];
                L_.path[kept] = L_.path[i];
                L_.visited[kept] = L_.visited[i];
                L_.events[kept] = L_.events[i];
                L_.phase[i] = kIdle;
            }
            ++kept;
        }
        lanes_ = kept;
    }

    const Sheet& sheet_;
    const dvec3 wi_, e1_, e2_;
    const double cone_;
    const std::vector<Grid>& grids_;
    const std::uint64_t n_;
    Tally& t_;
    const Rounds& run_;
    Rng rng_; // the rays' directions in a cone
    const bool averagedCube_;
    Lanes L_;
    BelowList B_;
    std::uint64_t started_ = 0;
    int lanes_ = 0; // the lanes in use, [0, lanes_): all of them until the rays run out
    int nb_ = 0;    // elements in the list below the surface
    int nd_ = 0;    // finished paths of this round
    int exiting_[kLanes], going_[kLanes], inside_[kLanes]; // lists of one loop each
    int attention_[kLanes], done_[kLanes], finished_[kLanes], hole_[kLanes], mover_[kLanes];
    // Exits waiting for their cells.
    int ne_ = 0;
    alignas(64) double exitX_[kLanes], exitY_[kLanes], exitZ_[kLanes];
    alignas(64) std::int64_t cell_[kLanes];
    int channel_[kLanes];
    bool single_[kLanes];
};

} // namespace

void grid_cells(const Grid& g, const double* wx, const double* wy, const double* wz, int n,
                std::int64_t* cell, SimdLevel level) {
    grid_cells(g, wx, wy, wz, n, cell, rounds(level));
}

void trace_chunk(const Sheet& sheet, const dvec3& wi, const dvec3& e1, const dvec3& e2, double cone,
                 const std::vector<Grid>& grids, std::uint64_t seed, std::uint64_t chunk,
                 std::uint64_t n, Tally& t, SimdLevel level) {
    Chunk(sheet, wi, e1, e2, cone, grids, seed, chunk, n, t, level).run();
}

} // namespace tracing
} // namespace sim
} // namespace retroprism
