// test_wavefront.cpp: the simulator's wavefront tracer (sim/wavefront.cpp), which `simulate` runs,
// against the one-ray-at-a-time reference (trace_path): the same distribution of fates and exit
// directions on sheets that take every path of the wavefront (its vector rounds and the one-lane
// completions of what they leave out); the same bits whatever instruction set its rounds are
// compiled for; and the arithmetic-only pieces it shares with trace_path against their reference
// values. Every TEST_CASE is tagged [sim].
//
// Fixed seeds: the statistical checks state their significance, and their outcome is
// deterministic (a failure is a change of behaviour, not bad luck).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "batch.h"
#include "microgeometry.h"
#include "test_support.h"
#include "tracing.h"

using retroprism::Params;
using rptest::dir_deg;
using rptest::dvec3;
namespace sim = retroprism::sim;
namespace f64 = retroprism::f64;

namespace {

struct Case {
    std::string name;
    Params params;
    double thetaDeg, phiDeg;
    double coneDeg = 0;
    bool upward = true; // upward_through_prisms
};

Params params_of(double roughness, int prism, int era, double cant, double dihedral, double kd) {
    Params p;
    p.roughness = roughness;
    p.prism_reflection = prism;
    p.era_mode = era;
    p.cant_angle = cant;
    p.dihedral_error = dihedral;
    p.diffuse_color = {kd, kd, kd};
    return p;
}

sim::Tally run(const Case& c, sim::RunOptions::Tracer tracer, std::uint64_t rays,
               std::uint64_t seed, const std::vector<sim::Grid>& grids) {
    sim::Sheet sheet = sim::sheet_from_params(c.params);
    sheet.upward_through_prisms = c.upward;
    sim::RunOptions opt;
    opt.rays = rays;
    opt.seed = seed;
    opt.tracer = tracer;
    opt.incidence_cone = c.coneDeg * 3.14159265358979323846 / 180.0;
    return sim::simulate(sheet, dir_deg(c.thetaDeg, c.phiDeg), grids, opt).tally;
}

} // namespace

TEST_CASE("The wavefront's fates and exit directions are trace_path's, in distribution", "[sim]") {
    // Two samples of N rays each, one per tracer (different draws): the homogeneity chi-square
    // over the categories fate x (exit cell of a 12 x 12 hemisphere grid, by lobe) and the
    // counters' classes, categories with fewer than 10 rays in both merged into one. Each case
    // passes at significance 1e-4 (p > 1e-4); the cases cover the walk's views from below and
    // grazing rays (roughness 0.3 at 75 degrees), canted and imperfect cubes and the oriented mode
    // (their cube corners in the one-lane completion), metallized faces, the paper's way up, and
    // light over a cone.
    const std::vector<Case> cases = {
        {"tir, roughness 0.1, 30 deg",
         params_of(0.1, f64::RP_PRISM_TIR, f64::RP_ERA_AVERAGED, 0, 0, 0.8), 30, 0},
        {"metallized, roughness 0.3, 75 deg",
         params_of(0.3, f64::RP_PRISM_METALLIZED, f64::RP_ERA_AVERAGED, 0, 0, 0.6), 75, 40},
        {"ideal, way up direct, normal incidence",
         params_of(0.05, f64::RP_PRISM_IDEAL, f64::RP_ERA_AVERAGED, 0, 0, 0.5), 0, 0, 0, false},
        {"tir, cant -11, dihedral 4', 40 deg",
         params_of(0.1, f64::RP_PRISM_TIR, f64::RP_ERA_AVERAGED, -11, 4, 0.8), 40, 30},
        {"tir, oriented, 60 deg",
         params_of(0.2, f64::RP_PRISM_TIR, f64::RP_ERA_ORIENTED, 0, 0, 0.8), 60, 15},
        {"tir, cone of 10 deg about 45 deg",
         params_of(0.1, f64::RP_PRISM_TIR, f64::RP_ERA_AVERAGED, 0, 0, 0.8), 45, 0, 10}};
    const std::vector<sim::Grid> grids = {sim::disk_grid("hemisphere", 12)};
    const std::uint64_t n = 200000;
    double worstP = 1;
    for (const Case& c : cases) {
        const sim::Tally a = run(c, sim::RunOptions::kWavefront, n, 11, grids);
        const sim::Tally b = run(c, sim::RunOptions::kScalar, n, 12, grids);
        REQUIRE(a.rays == n);
        REQUIRE(b.rays == n);
        std::vector<std::pair<double, double>> cats;
        for (int f = 0; f < sim::kFates; ++f)
            if (f != sim::kFateSurface && f != sim::kFateRetro && f != sim::kFateDiffuse)
                cats.push_back({double(a.fates[size_t(f)]), double(b.fates[size_t(f)])});
        for (int cell = 0; cell < grids[0].cells(); ++cell)
            for (int ch : {sim::kSurface, sim::kSurfaceSingle, sim::kRetro, sim::kDiffuse}) {
                const size_t k = size_t(cell) * sim::kChannels + size_t(ch);
                cats.push_back({double(a.counts[0][k]), double(b.counts[0][k])});
            }
        cats.push_back({double(a.retro_primary), double(b.retro_primary)});
        cats.push_back({double(a.retro_multiple), double(b.retro_multiple)});
        // Equal sample sizes: sum (a - b)^2 / (a + b) is chi-square with (categories - 1)
        // degrees of freedom under homogeneity.
        double chi2 = 0, sparseA = 0, sparseB = 0;
        int dof = -1;
        for (const auto& [x, y] : cats) {
            if (x + y < 10) {
                sparseA += x;
                sparseB += y;
                continue;
            }
            chi2 += (x - y) * (x - y) / (x + y);
            ++dof;
        }
        if (sparseA + sparseB > 0) {
            chi2 += (sparseA - sparseB) * (sparseA - sparseB) / (sparseA + sparseB);
            ++dof;
        }
        const double p = rptest::chi2_sf(chi2, dof);
        INFO(c.name << ": chi2 " << chi2 << " on " << dof << " dof, p " << p);
        CHECK(p > 1e-4);
        // The counters' means (substrate hits, face transmissions, internal reflections per ray)
        // within 4.4 combined standard errors (significance 1e-5 each, normal approximation; the
        // per-ray count's variance bounded by its second moment, taken as mean (1 + mean) x 4).
        const auto close = [n](std::uint64_t x, std::uint64_t y) {
            const double mx = double(x) / double(n), my = double(y) / double(n);
            const double var = 4.0 * (mx * (1 + mx) + my * (1 + my)) / double(n);
            return std::abs(mx - my) <= 4.4 * std::sqrt(var) + 1e-12;
        };
        CHECK(close(a.substrate_hits, b.substrate_hits));
        CHECK(close(a.face_transmissions, b.face_transmissions));
        CHECK(close(a.internal_reflections, b.internal_reflections));
        worstP = std::min(worstP, p);
    }
    std::printf("MEASURED: wavefront against trace_path, %zu sheets x 2 x %llu rays: smallest "
                "homogeneity p %.3g (bound 1e-4)\n",
                cases.size(), static_cast<unsigned long long>(n), worstP);
}

TEST_CASE("The wavefront gives the same bits whatever instruction set runs its rounds", "[sim]") {
    // One chunk through the rounds compiled for each instruction set this CPU runs (each round is
    // IEEE arithmetic without contraction or library calls): tallies equal bit for bit.
    for (const Params& params :
         {params_of(0.1, f64::RP_PRISM_TIR, f64::RP_ERA_AVERAGED, 0, 0, 0.8),
          params_of(0.3, f64::RP_PRISM_METALLIZED, f64::RP_ERA_AVERAGED, 8, 3, 0.6)}) {
        const sim::Sheet sheet = sim::sheet_from_params(params);
        const dvec3 wi = dir_deg(50, 10);
        const std::vector<sim::Grid> grids = sim::standard_grids(sheet, wi);
        dvec3 e1, e2;
        sim::lobe_frame(wi, e1, e2);
        const auto chunk = [&](retroprism::SimdLevel level) {
            sim::Tally t;
            t.counts.resize(grids.size());
            for (size_t g = 0; g < grids.size(); ++g)
                t.counts[g].assign(size_t(grids[g].cells()) * sim::kChannels, 0);
            sim::tracing::trace_chunk(sheet, wi, e1, e2, 0.0, grids, 5, 2, sim::kChunkRays, t,
                                      level);
            return t;
        };
        const sim::Tally base = chunk(retroprism::SimdLevel::Baseline);
        CHECK(base.rays == sim::kChunkRays);
        int levels = 1;
        for (retroprism::SimdLevel level :
             {retroprism::SimdLevel::Sse42, retroprism::SimdLevel::Avx2,
              retroprism::SimdLevel::Avx512}) {
            if (level > retroprism::simd_level_supported()) continue;
            const sim::Tally t = chunk(level);
            INFO(retroprism::simd_level_name(level));
            CHECK(t.fates == base.fates);
            CHECK(t.counts == base.counts);
            CHECK(t.substrate_hits == base.substrate_hits);
            CHECK(t.internal_reflections == base.internal_reflections);
            ++levels;
        }
        std::printf("MEASURED: one chunk through %d instruction sets: identical tallies\n", levels);
    }
}

TEST_CASE("The walk's depth from the other side and the faces' Fresnel terms are exact", "[sim]") {
    // depth_flip(l) = -log(1 - exp(-l)) against long double (64-bit mantissa; -log(-expm1(-l))
    // below ln 2, -log1p(-exp(-l)) above) over l from 1e-300 to 745.2, relative, or within the
    // least subnormal where the result is subnormal (l > 708); and its ends: +inf at 0, 0 at
    // +inf.
    double worst = 0;
    for (int k = 0; k <= 200000; ++k) {
        const double l = std::pow(10.0, -300.0 + 302.8451 * k / 200000.0); // up to 700
        const long double ll = l;
        const long double exact =
            l <= 0.5 ? -std::log(-std::expm1(-ll)) : -std::log1p(-std::exp(-ll));
        const double got = sim::tracing::depth_flip(l);
        worst = std::max(worst, double(std::abs((got - exact) / exact)));
    }
    for (double l = 700; l <= 745.2; l += 0.01) {
        const long double exact = -std::log1p(-std::exp(-(long double)l));
        CHECK(std::abs(sim::tracing::depth_flip(l) - exact) <=
              std::max(6.7e-16L * exact, 0x1p-1074L));
    }
    INFO("worst relative error " << worst);
    CHECK(worst < 6.7e-16); // three ulps
    CHECK(sim::tracing::depth_flip(0.0) == HUGE_VAL);
    CHECK(sim::tracing::depth_flip(HUGE_VAL) == 0.0);
    // internal_reflectance_terms n / d against the core's rp_fresnel_internal below the critical
    // angle.
    double worstF = 0;
    for (double eta : {1.05, 1.49, 1.586, 2.4})
        for (int k = 0; k <= 2000; ++k) {
            const double cCrit = std::sqrt(1.0 - 1.0 / (eta * eta));
            const double c = cCrit + (1.0 - cCrit) * k / 2000.0;
            double num, den;
            sim::tracing::internal_reflectance_terms(c, eta, num, den);
            const double f = f64::rp_fresnel_internal(c, eta);
            worstF = std::max(worstF, std::abs(num / den - f) / std::max(f, 1e-300));
        }
    INFO("worst relative error of the Fresnel terms " << worstF);
    CHECK(worstF < 1e-13);
    std::printf("MEASURED: depth_flip within %.2e relative of long double; the faces' Fresnel "
                "terms within %.2e of the core's\n",
                worst, worstF);
}

TEST_CASE("The tally's arctangents are libm's to the last bits", "[sim]") {
    // atan_unit over 1e6 points of [-1, 1] (and 0, +-1, tiny and subnormal values), atan2_of
    // over 1e6 pairs of every sign and ratio (and zeros): the largest difference from libm's
    // atan and atan2, in units of the result's last place. libm's are within 1 ulp of the exact
    // values; atan_unit adds the table's and the series' roundings (2 ulps allowed), atan2_of
    // one more rounding for its reflections pi/2 - r and pi - r (3 ulps allowed).
    retroprism::Rng rng(11, 0);
    const auto ulps = [](double got, double want) {
        if (got == want) return 0.0;
        const double ulp = std::nextafter(std::abs(want), HUGE_VAL) - std::abs(want);
        return std::abs(got - want) / ulp;
    };
    double worst = 0, worst2 = 0;
    std::vector<double> zs = {0.0, -0.0, 1.0, -1.0, 1e-300, -4e-320, 0.0625, 0.1875, 0.5};
    for (int k = 0; k < 1000000; ++k)
        zs.push_back(2.0 * rng.uniform() - 1.0);
    for (double z : zs)
        worst = std::max(worst, ulps(sim::tracing::atan_unit(z), std::atan(z)));
    for (int k = 0; k < 1000000; ++k) {
        const double y = (2.0 * rng.uniform() - 1.0) * std::pow(10.0, 4.0 * rng.uniform() - 2.0);
        const double x = (2.0 * rng.uniform() - 1.0) * std::pow(10.0, 4.0 * rng.uniform() - 2.0);
        worst2 = std::max(worst2, ulps(sim::tracing::atan2_of(y, x), std::atan2(y, x)));
    }
    for (double y : {0.0, 1.0, -1.0})
        for (double x : {0.0, 1.0, -1.0})
            if (!(y == 0 && x == 0))
                worst2 = std::max(worst2, ulps(sim::tracing::atan2_of(y, x), std::atan2(y, x)));
    CHECK(sim::tracing::atan2_of(0.0, 0.0) == 0.0);
    CHECK(worst <= 2.0);
    CHECK(worst2 <= 3.0);
    std::printf("MEASURED: atan_unit within %.2f ulp of libm's atan, atan2_of within %.2f ulp of "
                "atan2\n",
                worst, worst2);
}

TEST_CASE("The wavefront's tally finds Grid::cell_of's cells on every instruction set", "[sim]") {
    // The standard grids at 30 and 75 degrees and a cone: 4e5 directions each (uniform over the
    // sphere, and about the retro and mirror directions within 3 slopes of their lobes) through
    // grid_cells and through Grid::cell_of. They differ only where a parameter falls within an
    // ulp or two of a cell's edge (the arctangents' last bits), some 1e-13 of directions: none
    // expected.
    retroprism::Rng rng(12, 0);
    const sim::Sheet sheet =
        sim::sheet_from_params(params_of(0.1, f64::RP_PRISM_TIR, f64::RP_ERA_AVERAGED, 0, 0, 0.8));
    long compared = 0, differ = 0, inside = 0;
    for (double theta : {30.0, 75.0}) {
        const dvec3 wi = dir_deg(theta, 20);
        std::vector<sim::Grid> grids = sim::standard_grids(sheet, wi);
        grids.push_back(sim::cone_grid("cone", wi, 0.05));
        const dvec3 mirror(-wi.x, -wi.y, wi.z);
        const int n = 400000;
        std::vector<double> wx(n), wy(n), wz(n);
        for (int k = 0; k < n; ++k) {
            dvec3 w;
            if (k % 3 == 0) { // uniform over the sphere
                const double z = 2.0 * rng.uniform() - 1.0,
                             phi = 2.0 * 3.14159265358979 * rng.uniform();
                const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
                w = dvec3(r * std::cos(phi), r * std::sin(phi), z);
            } else { // about wi or the mirror direction
                const dvec3 c = k % 3 == 1 ? wi : mirror;
                w = glm::normalize(c + 0.3 * dvec3(2.0 * rng.uniform() - 1.0,
                                                   2.0 * rng.uniform() - 1.0,
                                                   2.0 * rng.uniform() - 1.0));
            }
            wx[size_t(k)] = w.x;
            wy[size_t(k)] = w.y;
            wz[size_t(k)] = w.z;
        }
        for (const sim::Grid& g : grids) {
            std::vector<int> want(size_t(n), 0);
            for (int k = 0; k < n; ++k)
                want[size_t(k)] = g.cell_of(dvec3(wx[size_t(k)], wy[size_t(k)], wz[size_t(k)]));
            for (retroprism::SimdLevel level :
                 {retroprism::SimdLevel::Baseline, retroprism::SimdLevel::Sse42,
                  retroprism::SimdLevel::Avx2, retroprism::SimdLevel::Avx512}) {
                if (level > retroprism::simd_level_supported()) continue;
                std::vector<std::int64_t> got(size_t(n), 0);
                sim::tracing::grid_cells(g, wx.data(), wy.data(), wz.data(), n, got.data(), level);
                for (int k = 0; k < n; ++k) {
                    ++compared;
                    inside += want[size_t(k)] >= 0;
                    differ += got[size_t(k)] != want[size_t(k)];
                }
            }
        }
    }
    CHECK(differ == 0);
    CHECK(inside > compared / 10); // the directions reach into every grid
    std::printf("MEASURED: grid_cells against Grid::cell_of: %ld of %ld cells differ (%ld inside "
                "a grid)\n",
                differ, compared, inside);
}
