// microgeometry.h: the ground truth of the prismatic retroreflector BRDF (MODEL.md section 6): a
// Monte Carlo simulation, in geometric optics and in double, of light paths through the explicit
// microgeometry of the sheet, against which every approximation of the analytic model
// (prism_core.inc) is measured.
//
// What is simulated (one light path per ray, unit weight, every decision by Russian roulette,
// so that every ray ends in exactly one fate):
//  1. The rough top surface (Beckmann roughness alpha, index eta) is crossed by the random walk
//     of Heitz, Hanika, d'Eon & Dachsbacher 2016
//     ("Multiple-scattering microfacet BSDFs with the Smith model") on a dielectric Smith
//     microsurface: the next intersection height from the Smith masking function, a visible
//     Beckmann microfacet (Heitz & d'Eon 2014, for views from above *and* from below the mean
//     plane), the exact Fresnel choice between reflection and refraction at the microfacet
//     (rp_fresnel_dielectric / rp_fresnel_internal of the core), repeated until the ray leaves
//     the microsurface upward (outside) or downward (into the sheet). Nothing is lost at the
//     surface: a masked ray hits the surface again. Paths that leave after exactly one
//     scattering event are the height-correlated single-scattering microfacet model, i.e. the
//     analytic surface lobe f_s and its single refraction; the higher orders are tallied
//     separately (the analytic model has none).
//  2. A ray refracted into the sheet meets a cube corner (apex O, faces with normals
//     e_k = (sqrt(2/3) v_k, 1/sqrt3), v_k the aperture vertex directions of the prism's
//     orientation; a canted cube's in sim/cube_corner.h) at a uniformly distributed point of its
//     aperture triangle and is traced exactly: each face hit reflects (ideal: always; tir: with the
//     internal Fresnel reflectance at the hit's cosine, else the ray is transmitted through the
//     face; metallized: with metal_reflectance, else it is absorbed). After one reflection on each
//     of the three faces the ray leaves along -d (retroreflected) and goes back up to the top
//     surface. The orientation: fixed (era_mode oriented), one of the matched pair (probability 1/2
//     each), or uniformly random per encounter (averaged).
//  3. A ray that is not retroreflected (it leaves the aperture after one or two reflections, or
//     is transmitted through a face) is handed to the Lambertian substrate below the prisms:
//     MODEL.md's layer abstraction
//     ("light refracted in but not retroreflected reaches the substrate"), which the analytic
//     diffuse lobe also assumes. The substrate absorbs it with probability 1 - k_d, else
//     re-emits it upward, cosine-distributed in the sheet.
//  4. The way back up (Sheet::upward_through_prisms, default true): light from the substrate
//     crosses the prism layer as the exact adjoint of the way down: a cube corner is traced for
//     the reversed direction -u; where that trace is retroreflected the upward light is sent
//     back to the substrate, where it is absorbed by a metallized face it is absorbed, otherwise
//     it passes up with direction u. The layer is then reciprocal (the probability that upward
//     light passes in direction u equals that of downward light along -u reaching the
//     substrate), and so is the simulated BRDF. With false, the substrate's light goes straight
//     to the top surface and internal reflections of it go straight back to the substrate: the
//     paper's assumption ((1 - E) at entry only, the F_dr interreflection), not reciprocal.
//  5. Upward light crosses the top surface from inside by the same random walk; what is
//     reflected back down (internal reflection, F_dr for diffuse light) meets the prisms again
//     (or, with upward_through_prisms false and after the substrate, the substrate directly).
//     What leaves upward is an exit: the surface lobe if the ray never entered, the retro lobe
//     if it entered and never reached the substrate, the diffuse lobe otherwise.
//
// Fates (every ray exactly one): exit as surface, retro or diffuse; absorbed by the substrate;
// absorbed by a metallized face; trapped (more than kMaxEvents events or kMaxWalkOrder
// scattering events in one crossing; 0 in practice). A lossless sheet (k_d = 1, ideal or tir
// faces) reflects every ray but the trapped ones.
//
// The analytic model's colour and artistic weights (retro_color, specular, weight) multiply its
// lobes and are not geometry: the simulator works for one scalar substrate albedo k_d (one
// colour channel) and the CLI applies those factors to its tallies.
//
// Estimates: exit directions are tallied per path category in grids of cells (Grid: a gnomonic
// grid of slopes about the retro or mirror direction, a concentric equal-area grid of the
// projected hemisphere, in-plane strips, cones). A cell's BRDF estimate is its cosine-weighted
// average f = count / (N * Omega_p), Omega_p = integral of cos(theta_o) over the cell, with the
// binomial standard error sqrt(count (1 - count / N)) / (N Omega_p); analytic values are
// integrated over the same cells (integrate_cells), so both sides are cell averages.
//
// Determinism: rays are processed in fixed chunks of kChunkRays, each chunk's random streams
// derived from (seed, chunk) alone (one for trace_path; the wavefront's one per lane and per
// position of its list below the surface, sim/wavefront.cpp), and all tallies are integers: the
// result depends on the seed and the tracer only, not on the number of threads, nor on the
// instruction set that runs the wavefront.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "prismatic_retroreflector.h"
#include "rng.h"

namespace retroprism {
namespace sim {

using dvec2 = glm::dvec2;
using dvec3 = glm::dvec3;

// The physical sheet. Angles and enums as in the node's parameters.
struct Sheet {
    double alpha = 0.05; // Beckmann roughness of the top surface
    double eta = 1.49;   // index of the sheet
    int prism_reflection = f64::RP_PRISM_IDEAL;
    double metal_reflectance = 0.88; // one metallized face
    int era_mode = f64::RP_ERA_AVERAGED;
    double orientation_deg = 0.0; // of one aperture vertex from the tangent (+x)
    double cant_deg = 0.0;        // cant_angle: 0 the paper's cube, else sim/cube_corner.h
    double dihedral_arcmin = 0.0; // dihedral_error: 0 the perfect cube, else sim/cube_corner.h
    double dihedral_spread_arcmin = 0.0; // dihedral_spread: each prism's three dihedral errors
                                         // drawn about dihedral_arcmin with this deviation
    double kd = 0.9;                     // substrate albedo, one channel
    bool upward_through_prisms = true;
};

// The sheet of the node's parameters (sanitised: roughness floored at RP_MIN_ALPHA like the
// node), for colour channel `channel` of diffuse_color.
Sheet sheet_from_params(const Params& p, int channel = 0);

// Limits of one path. Trapped rays are counted, never dropped.
constexpr int kMaxEvents = 100000;  // prism, substrate and top-surface events of one path
constexpr int kMaxWalkOrder = 1000; // scattering events of one top-surface crossing
// Rays per chunk: enough that the wavefront's last rounds of a chunk, with fewer rays in flight
// than lanes, cost little (2% more throughput than 4096), few enough that two threads finish a
// run of 4e6 rays within one chunk's time of each other (244 chunks).
constexpr std::uint64_t kChunkRays = 16384;

// ---- Random numbers ------------------------------------------------------------------------

// util/rng.h: xoshiro256** seeded through splitmix64 from (seed, stream), independent streams
// per chunk.
using Rng = retroprism::Rng;

// ---- Building blocks (exposed for the tests) ----------------------------------------------

// Smith Lambda of the Beckmann surface for a direction of either hemisphere
// (Lambda(-w) = -1 - Lambda(w)).
double smith_lambda(const dvec3& w, double alpha);

// A microfacet normal distributed as the visible normals of the Beckmann surface seen from w
// (density max(0, w.m) D(m) / integral), for any w not pointing straight down: views from below
// the mean plane, which the random walk needs, included. Unit, m.z > 0.
dvec3 sample_visible_normal(const dvec3& w, double alpha, Rng& rng);

// One crossing of the rough top surface by the random walk. `dir` is the ray's direction of
// travel: downward for light arriving from outside (from_outside = true), upward for light
// arriving from inside the sheet.
struct Crossing {
    dvec3 dir{0.0};       // direction after the walk
    bool outside = false; // left upward into the air (else downward into the sheet)
    int order = 0;        // scattering events on the microsurface
    bool trapped = false; // kMaxWalkOrder exceeded
};
Crossing cross_top_surface(const Sheet& sheet, const dvec3& dir, bool from_outside, Rng& rng);

// A cube corner met by a downward ray of direction d (unit, d.z < 0) at a uniform point of its
// aperture. A retroreflected ray leaves along -d, or, with dihedral errors, along the direction
// its three reflections give; `exit` (when not null) receives that direction.
enum PrismOutcome : std::int64_t { // 64 bits wide: vectorised with doubles (sim/wavefront.cpp)
    kPrismRetro,                   // three reflections: leaves along -d
    kPrismMiss,                    // leaves the aperture after fewer reflections
    kPrismTransmitted,             // transmitted through a face (tir)
    kPrismAbsorbed                 // absorbed by a face (metallized)
};
PrismOutcome trace_prism(const Sheet& sheet, const dvec3& d, Rng& rng, dvec3* exit = nullptr);

// ---- Paths ----------------------------------------------------------------------------------

enum Fate {
    kFateSurface = 0,
    kFateRetro,
    kFateDiffuse,
    kFateAbsorbedSubstrate,
    kFateAbsorbedFaces,
    kFateTrapped,
    kFates
};
const char* fate_name(int fate);

struct Path {
    int fate = kFateTrapped;
    dvec3 wo{0.0};                // exit direction (exits only)
    int surface_order = 0;        // scattering order of the top-surface walk (surface exits)
    int retroreflections = 0;     // cube-corner retroreflections on the way
    int internal_reflections = 0; // returns from the top surface into the sheet
    int substrate_hits = 0;
    int face_transmissions = 0; // tir transmissions through a face (to the substrate)
};

// One light path for light arriving from wi (unit, wi.z > 0).
Path trace_path(const Sheet& sheet, const dvec3& wi, Rng& rng);

// ---- Grids ----------------------------------------------------------------------------------

// Tally channels of a cell: exits of the surface lobe (all scattering orders), its
// single-scattering part, the retro lobe, the diffuse lobe.
enum Channel { kSurface = 0, kSurfaceSingle, kRetro, kDiffuse, kChannels };
const char* channel_name(int channel);

// A grid of cells on the sphere of exit directions: nx * ny cells over the parameter rectangle
// [x0, x1] x [y0, y1], cell (i, j) = index j * nx + i.
//  - kGnomonic: slopes (x, y) about centre c: w = normalize(c + x e1 + y e2).
//  - kDisk: the concentric (Shirley-Chiu) map of the square [-1, 1]^2 onto the unit disk of the
//    projected hemisphere, w = (px, py, sqrt(1 - px^2 - py^2)): every cell has the projected
//    solid angle pi / (nx ny).
//  - kStrip: angles (x, y) in radians, w = cos y (sin x e1 + cos x c) + sin y e2: a band of
//    half-width y1 about the great circle through c and e1.
//  - kCone: polar (x = angle from c, y = azimuth about c in the frame e1, e2); one cell.
struct Grid {
    enum Kind { kGnomonic, kDisk, kStrip, kCone };
    Kind kind = kDisk;
    std::string name;
    dvec3 c{0, 0, 1}, e1{1, 0, 0}, e2{0, 1, 0};
    double x0 = -1, x1 = 1, y0 = -1, y1 = 1;
    int nx = 1, ny = 1;

    int cells() const { return nx * ny; }
    // Parameters of a direction; false when it has none (behind a gnomonic centre).
    bool params(const dvec3& w, double& x, double& y) const;
    // Direction of parameters (x, y) and dOmega / (dx dy).
    dvec3 direction(double x, double y, double& jacobian) const;
    // Cell of a direction, -1 outside the grid.
    int cell_of(const dvec3& w) const;
    // Centre direction of a cell (its parameter midpoint).
    dvec3 cell_centre(int cell) const;
};

Grid gnomonic_grid(const std::string& name, const dvec3& centre, const dvec3& e1, const dvec3& e2,
                   double halfX, double halfY, int nx, int ny);
Grid disk_grid(const std::string& name, int n);
Grid strip_grid(const std::string& name, const dvec3& c, const dvec3& e1, int n,
                double halfWidthRad);
Grid cone_grid(const std::string& name, const dvec3& axis, double radiusRad);

// The lobe frame about a direction w: ePerp = normalize(n x w) (the tangent's y axis at normal
// incidence), ePar = ePerp x w, as the core's retro lobe frame: positive ePar slopes tilt away
// from the normal in the plane of incidence.
void lobe_frame(const dvec3& w, dvec3& ePar, dvec3& ePerp);

// The standard grids of one incident direction, in this order: "retro" (gnomonic about wi,
// half-widths kLobeSpan times the widest retro width of the analytic variants, at most slope
// kMaxSlope, nLobe^2 cells), "mirror" (gnomonic about the mirror direction, half-width
// kLobeSpan * 2 alpha), "hemisphere" (disk, nDisk^2 cells), "in_plane" (strip through the
// normal along the plane of incidence, 2-degree cells, x > 0 on the light's side),
// "across" (strip through wi perpendicular to the plane of incidence, 2-degree cells).
struct GridOptions {
    int nLobe = 41;
    int nDisk = 48;
    int nStrip = 90;
    double stripHalfWidthDeg = 2.0;
};
constexpr double kLobeSpan = 4.0;
constexpr double kMaxSlope = 3.0;
std::vector<Grid> standard_grids(const Sheet& sheet, const dvec3& wi,
                                 const GridOptions& opt = GridOptions());

// ---- Simulation -------------------------------------------------------------------------------

struct Tally {
    std::uint64_t rays = 0;
    std::array<std::uint64_t, kFates> fates{};
    std::uint64_t retro_primary = 0;  // retro exits: one retroreflection, no internal reflection
    std::uint64_t retro_multiple = 0; // retro exits with more than one retroreflection
    std::uint64_t surface_single = 0; // surface exits after one scattering event
    std::uint64_t substrate_hits = 0;
    std::uint64_t face_transmissions = 0;
    std::uint64_t internal_reflections = 0;
    std::vector<std::vector<std::uint64_t>> counts; // [grid][cell * kChannels + channel]

    void add(const Tally& o);
    std::uint64_t reflected() const {
        return fates[kFateSurface] + fates[kFateRetro] + fates[kFateDiffuse];
    }
};

struct RunOptions {
    // Called with rays done, rays in all.
    using Progress = std::function<void(std::uint64_t, std::uint64_t)>;
    std::uint64_t rays = 1000000;
    std::uint64_t seed = 1;
    int threads = 0; // 0: one per core (util/parallel.h thread_count)
    // > 0: every ray arrives from its own direction, drawn over the cone of this half-angle
    // about wi with density proportional to cos(theta) (the projected solid angle): then the
    // tallies estimate integrals over pairs of regions, Q(A, B) / Omega_p(A), which reciprocity
    // makes exactly symmetric (the exact test of reciprocity, free of the cones' widths).
    double incidence_cone = 0;
    // Called on the calling thread about every 0.1 s: rays done, rays in all.
    Progress progress;
    // The tracer: the wavefront of sim/wavefront.cpp (many rays in SIMD lanes), or trace_path one
    // ray at a time (the reference the wavefront is tested against). The two draw their random
    // numbers differently: the same statistics, not the same bits. kAuto: the wavefront where the
    // CPU has AVX-512, else trace_path (faster than the wavefront's rounds in AVX2's four lanes,
    // which lack AVX-512's conversions between 64-bit integers and doubles).
    enum Tracer { kAuto, kWavefront, kScalar };
    Tracer tracer = kAuto;
};

struct Run {
    Tally tally;
    double seconds = 0;
    int threads = 1;
    double rays_per_second() const { return seconds > 0 ? double(tally.rays) / seconds : 0; }
};

Run simulate(const Sheet& sheet, const dvec3& wi, const std::vector<Grid>& grids,
             const RunOptions& opt);

// ---- Estimates and analytic integrals over cells
// -------------------------------------------------

struct Estimate {
    double value = 0;
    double se = 0; // standard error
};
// Fraction count / n and its binomial standard error.
Estimate fraction(std::uint64_t count, std::uint64_t n);

// A narrow feature that the cell quadrature must resolve: its centre and angular width.
struct Feature {
    dvec3 dir;
    double width;
};

// Cell integrals of a function over a grid: for every cell, the projected solid angle
// (integral of cos theta over its part above the horizon), the parameter area of that part, and
// the integrals of the K values of f times cos theta (K = values.size() / cells). Midpoint rule
// on S x S sub-cells, S = minS, raised near a feature to resolve it (at most maxS).
struct CellIntegrals {
    int k = 0;
    std::vector<double> projected;
    std::vector<double> param_area;
    std::vector<double> values; // [cell * k + i]
};
using CellFunction = std::function<void(const dvec3& wo, double* out)>;
CellIntegrals integrate_cells(const Grid& g, int k, const CellFunction& f,
                              const std::vector<Feature>& features, int minS = 3, int maxS = 64,
                              int threads = 0);

// BRDF estimate of a cell and channel (cosine-weighted cell average) from a tally.
Estimate cell_brdf(const Tally& t, int grid, int cell, int channel, double projected);

// The analytic node's lobes (surface, retro, diffuse; channel 0 of each colour, weight
// included) as a CellFunction for incident direction wi.
CellFunction model_function(const Params& params, const dvec3& wi);
// The same for a prepared material and an incident state at wi that the caller may have changed
// (a variant of a lobe, such as a different shape of the ring of spots).
CellFunction model_function(const f64::rp_material& m, const f64::rp_incident& s, const dvec3& wi);

// Weighted least-squares fit of log(density) = c0 + c1 x + c2 y - x^2 / ax^2 - y^2 / ay^2 over
// the cells of a gnomonic grid with use[cell] != 0 (density > 0), weights w[cell] (the inverse
// variance of log density: the cell's count for Monte Carlo data).
struct LobeFit {
    bool ok = false;
    double ax = 0, ay = 0;       // fitted Beckmann widths along e1 and e2
    double se_ax = 0, se_ay = 0; // their standard errors (scaled by the reduced chi-square if > 1)
    double mx = 0, my = 0;       // centre of the fitted Gaussian (slopes)
    int cells = 0;
    double chi2_reduced = 0;
};
LobeFit fit_lobe(const Grid& g, const std::vector<double>& density, const std::vector<double>& w,
                 const std::vector<char>& use);

} // namespace sim
} // namespace retroprism
