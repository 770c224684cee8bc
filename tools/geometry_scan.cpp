// geometry_scan: which cube-corner geometries could reproduce a measured R_A table, by geometric
// optics alone: truncated cubes, or with `--full` arrays of full cubes (sim/cube_corner.h). For
// each cant and each triple of dihedral errors of a grid (the three errors equal, one or two of
// them set, of either sign: per-face errors that the node's inputs do not offer), the microgeometry
// simulator's pieces trace a matched pair of ideal prisms under a rough top surface (the Smith walk
// of sim/microgeometry.h): rays enter at each entry's entrance angle, the retroreflected ones leave
// through the surface, and R_A is the count in a cone of kWindowDeg about the entry's observation
// direction per ray and steradian times cos(entrance), the mean over rotations 0 and 90 degrees
// where the entry has no rotation (the entries of one entrance and rotation share their rays;
// "fewest" is the smallest count behind an entry, whose relative standard error is about 1 / sqrt
// of it). Each geometry's values are scaled by the one factor that best fits the table in log space
// (the level that retro_color, the metallisation and the substrate set), and ranked by their worst
// entry.
//
//   retroprism_geometry_scan [--full] TABLE.csv [ROUGHNESS [RAYS]]
//   retroprism_geometry_scan --wave TABLE.csv [PITCH_UM,... [tir|ideal|metallized]]
//
// ROUGHNESS: Beckmann roughness of the top surface (default 0.008); RAYS: rays per entrance and
// rotation (default 1e5). Deterministic: fixed seeds per geometry, whatever the thread count.
// `--wave`: the same grid of truncated cubes in physical optics instead (sim/wave_optics.h,
// docs/wave_optics.md), prisms of ior 1.49 (uncoated, TIR, unless named otherwise) with a
// smooth top surface, at each pitch (default 80,120,162,200,250 um): matched pairs, the coplanar
// observation, photometric (illuminant A x V), each geometry and pitch with its own scale.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "cube_corner.h"
#include "error.h"
#include "microgeometry.h"
#include "parallel.h"
#include "parse.h"
#include "photometry.h"
#include "ra_table.h"
#include "wave_optics.h"

using namespace retroprism;
using glm::dvec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kWindowDeg = 0.04; // half-angle of the cone about each observation direction
constexpr double kEta = 1.49;

struct Geometry {
    bool full = false; // an array of full cubes (sim::trace_full_cube), cant 0
    double cant = 0.0;
    double errors[3] = {0.0, 0.0, 0.0}; // arcmin, between the two faces other than k
    std::vector<double> ra;             // per entry, before scaling
    std::uint64_t fewest = 0;           // the smallest count behind an entry
    double scale = 0.0;
    double worst = 0.0; // largest |scaled / measured - 1| over the entries
};

// The error triples of magnitude a: (a, a, a), (-a, -a, -a), (a, 0, 0), (-a, 0, 0), (0, a, 0),
// (a, a, 0), (0, a, a), (a, -a, 0), (a, 0, -a): a cant makes the faces unequal, so where a lone
// error sits matters.
void add_triples(std::vector<Geometry>& out, bool full, double cant, double a) {
    const double triples[9][3] = {{a, a, a}, {-a, -a, -a}, {a, 0, 0},  {-a, 0, 0}, {0, a, 0},
                                  {a, a, 0}, {0, a, a},    {a, -a, 0}, {a, 0, -a}};
    for (const auto& t : triples) {
        Geometry g;
        g.full = full;
        g.cant = cant;
        std::copy(t, t + 3, g.errors);
        out.push_back(g);
    }
}

// The grid of truncated cubes: cants from -15 to 15 degrees and error magnitudes of 2, 4, 6 and 9
// arcmin; of full cubes (`--full`): cant 0, the perfect cube and magnitudes of 1, 2, 3, 4, 6 and
// 9 arcmin.
std::vector<Geometry> grid(bool full) {
    std::vector<Geometry> out;
    if (full) {
        out.push_back(Geometry{true, 0.0, {0.0, 0.0, 0.0}, {}, 0, 0.0, 0.0});
        for (double a : {1.0, 2.0, 3.0, 4.0, 6.0, 9.0})
            add_triples(out, true, 0.0, a);
        return out;
    }
    for (double cant : {-15.0, -11.0, -7.0, -3.0, 0.0, 3.0, 7.0, 11.0, 15.0})
        for (double a : {2.0, 4.0, 6.0, 9.0})
            add_triples(out, false, cant, a);
    return out;
}

// The rays of one entrance, presentation and rotation, and the entries they serve: each entry's
// observation direction and its weight (1 over its rotations).
struct Beam {
    double entrance = 0.0, presentation = 0.0, rotation = 0.0;
    std::vector<std::size_t> entry;
    std::vector<dvec3> wo;
    std::vector<double> weight;
};

std::vector<Beam> beams_of(const std::vector<RaEntry>& entries) {
    std::vector<Beam> out;
    for (std::size_t e = 0; e < entries.size(); ++e) {
        const RaEntry& entry = entries[e];
        const std::vector<double> rotations = entry.rotation_deg
                                                  ? std::vector<double>{*entry.rotation_deg}
                                                  : std::vector<double>{0.0, 90.0};
        for (double rotation : rotations) {
            auto it = std::find_if(out.begin(), out.end(), [&](const Beam& b) {
                return b.entrance == entry.entrance_deg &&
                       b.presentation == entry.presentation_deg && b.rotation == rotation;
            });
            if (it == out.end()) {
                out.push_back({entry.entrance_deg, entry.presentation_deg, rotation, {}, {}, {}});
                it = out.end() - 1;
            }
            dvec3 wi, wo;
            ra_directions(entry.entrance_deg, entry.observation_deg, rotation, wi, wo,
                          entry.presentation_deg);
            it->entry.push_back(e);
            it->wo.push_back(wo);
            it->weight.push_back(1.0 / double(rotations.size()));
        }
    }
    return out;
}

// Simulated R_A (up to the common scale) of geometry g at each entry, and the smallest count
// behind one (its relative standard error is about 1 / sqrt of it).
std::vector<double> simulate_entries(const Geometry& g, const std::vector<Beam>& beams,
                                     std::size_t entries, double roughness, std::uint64_t rays,
                                     std::uint64_t seed, std::uint64_t& fewest) {
    sim::Sheet sheet;
    sheet.alpha = roughness;
    sheet.eta = kEta;
    sheet.prism_reflection = f64::RP_PRISM_IDEAL;
    sheet.dihedral_arcmin = 1.0; // trace_cube_corner then returns the traced exit direction
    const sim::CubeCorner pair[2] = {sim::cube_corner(g.cant, g.errors, 0.0),
                                     sim::cube_corner(g.cant, g.errors, kPi)};
    const sim::FullCubeArray fullPair[2] = {sim::full_cube_array(g.errors, 0.0),
                                            sim::full_cube_array(g.errors, kPi)};
    const double cosWindow = std::cos(kWindowDeg * kDeg);
    const double omega = 2.0 * kPi * (1.0 - cosWindow);
    std::vector<double> ra(entries, 0.0);
    fewest = ~std::uint64_t(0);
    for (std::size_t b = 0; b < beams.size(); ++b) {
        const Beam& beam = beams[b];
        dvec3 wi, wo;
        ra_directions(beam.entrance, 0.0, beam.rotation, wi, wo, beam.presentation);
        sim::Rng rng(seed, b);
        std::vector<std::uint64_t> count(beam.wo.size(), 0);
        for (std::uint64_t i = 0; i < rays; ++i) {
            const sim::Crossing in = sim::cross_top_surface(sheet, -wi, true, rng);
            if (in.trapped || in.outside) continue;
            dvec3 up;
            const sim::PrismOutcome outcome =
                g.full ? sim::trace_full_cube(sheet, fullPair[i & 1], in.dir, rng, &up)
                       : sim::trace_cube_corner(sheet, pair[i & 1], in.dir, rng, &up);
            if (outcome != sim::kPrismRetro) continue;
            const sim::Crossing out = sim::cross_top_surface(sheet, up, false, rng);
            if (out.trapped || !out.outside) continue;
            for (std::size_t k = 0; k < beam.wo.size(); ++k)
                count[k] += glm::dot(out.dir, beam.wo[k]) >= cosWindow ? 1 : 0;
        }
        for (std::size_t k = 0; k < beam.wo.size(); ++k) {
            ra[beam.entry[k]] += beam.weight[k] * double(count[k]) / (double(rays) * omega) * wi.z;
            fewest = std::min(fewest, count[k]);
        }
    }
    return ra;
}

// The scale that minimises the sum of squared log errors, and the worst relative error after it.
void fit_scale(Geometry& g, const std::vector<RaEntry>& entries) {
    double sumLog = 0.0;
    for (size_t e = 0; e < entries.size(); ++e) {
        if (!(g.ra[e] > 0)) {
            g.scale = 0.0;
            g.worst = 1.0; // an entry the geometry sends no light to
            return;
        }
        sumLog += std::log(entries[e].ra / g.ra[e]);
    }
    g.scale = std::exp(sumLog / double(entries.size()));
    g.worst = 0.0;
    for (size_t e = 0; e < entries.size(); ++e)
        g.worst = std::max(g.worst, std::abs(g.scale * g.ra[e] / entries[e].ra - 1.0));
}

// One geometry of the wave scan: the grid's corner at a pitch.
struct WaveGeometry {
    Geometry g;
    double pitch = 0.0;
};

// The photometric wave R_A of a matched pair of TIR prisms at each entry (the mean over its
// rotations, 0 and 90 degrees when it has none), coplanar observation.
std::vector<double> wave_entries(const Geometry& g, double pitch, int reflection,
                                 const std::vector<RaEntry>& entries) {
    sim::wave::WaveMaterial m;
    m.ior = kEta;
    m.prism_reflection = reflection;
    m.cant_deg = g.cant;
    std::copy(g.errors, g.errors + 3, m.dihedral_faces_arcmin.begin());
    m.pitch_um = pitch;
    sim::wave::WaveMode mode;
    mode.era = sim::wave::WaveMode::Era::kMatchedPair;
    mode.coplanar = true;
    std::vector<double> ra(entries.size(), 0.0);
    for (std::size_t e = 0; e < entries.size(); ++e) {
        const RaEntry& entry = entries[e];
        if (entry.presentation_deg != 0.0)
            throw InputError("line " + std::to_string(entry.line) +
                             ": --wave takes presentation angle 0 only");
        const std::vector<double> rotations = entry.rotation_deg
                                                  ? std::vector<double>{*entry.rotation_deg}
                                                  : std::vector<double>{0.0, 90.0};
        mode.rotations_deg = rotations;
        ra[e] = sim::wave::wave_ra_profile_photometric(m, entry.entrance_deg,
                                                       {entry.observation_deg}, mode)[0];
    }
    return ra;
}

int wave_scan(const RaMeasurements& table, const std::vector<double>& pitches,
              const std::string& reflection) {
    const char* names[3] = {"ideal", "tir", "metallized"};
    const int mode = int(std::find(names, names + 3, reflection) - names);
    if (mode == 3)
        throw InputError("reflection " + reflection + ": expected tir, ideal or metallized");
    std::vector<WaveGeometry> scan;
    for (const Geometry& g : grid(false))
        for (double pitch : pitches)
            scan.push_back({g, pitch});
    parallel_for(scan.size(), 0, [&](std::size_t i) {
        scan[i].g.ra = wave_entries(scan[i].g, scan[i].pitch, mode, table.entries);
        fit_scale(scan[i].g, table.entries);
    });
    std::sort(scan.begin(), scan.end(),
              [](const WaveGeometry& a, const WaveGeometry& b) { return a.g.worst < b.g.worst; });
    const auto within20 = std::count_if(scan.begin(), scan.end(),
                                        [](const WaveGeometry& w) { return w.g.worst <= 0.2; });
    std::printf("%zu geometries (matched pairs of %s prisms in physical optics, ior %.2f, smooth "
                "top surface, photometric, %zu pitches) against %s: %ld within 20%% at every "
                "entry\n",
                scan.size(), mode == 1 ? "TIR" : names[mode], kEta, pitches.size(),
                table.file.c_str(), long(within20));
    std::printf("\n%6s %6s %17s %7s  scaled / measured per entry\n", "pitch", "cant",
                "errors (arcmin)", "worst");
    for (size_t i = 0; i < std::min<size_t>(10, scan.size()); ++i) {
        const Geometry& g = scan[i].g;
        std::printf("%6.0f %6.1f %5.1f %5.1f %5.1f %6.1f%% ", scan[i].pitch, g.cant, g.errors[0],
                    g.errors[1], g.errors[2], 100.0 * g.worst);
        for (size_t e = 0; e < table.entries.size(); ++e)
            std::printf(" %5.2f", g.scale * g.ra[e] / table.entries[e].ra);
        std::printf("\n");
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    try {
        if (argc > 1 && std::string(argv[1]) == "--wave") {
            if (argc < 3 || argc > 5) {
                std::fprintf(stderr, "usage: retroprism_geometry_scan --wave TABLE.csv "
                                     "[PITCH_UM,... [tir|ideal|metallized]]\n");
                return 2;
            }
            return wave_scan(
                read_ra_table(argv[2]),
                parse_number_list(argc > 3 ? argv[3] : "80,120,162,200,250", "PITCH_UM", 1, 1e5),
                argc > 4 ? argv[4] : "tir");
        }
        const bool full = argc > 1 && std::string(argv[1]) == "--full";
        const int first = full ? 2 : 1; // the first positional argument
        if (argc < first + 1 || argc > first + 3) {
            std::fprintf(stderr,
                         "usage: retroprism_geometry_scan [--full] TABLE.csv [ROUGHNESS [RAYS]]\n");
            return 2;
        }
        const RaMeasurements table = read_ra_table(argv[first]);
        const double roughness =
            argc > first + 1 ? parse_number_in(argv[first + 1], "ROUGHNESS", 1e-3, 0.5) : 0.008;
        const std::uint64_t rays =
            argc > first + 2 ? parse_count(argv[first + 2], "RAYS", 1e3, 1e9) : 100000;
        std::vector<Geometry> geometries = grid(full);
        const std::vector<Beam> beams = beams_of(table.entries);
        parallel_for(geometries.size(), 0, [&](std::size_t i) {
            Geometry& g = geometries[i];
            g.ra = simulate_entries(g, beams, table.entries.size(), roughness, rays, 1000 + i,
                                    g.fewest);
            fit_scale(g, table.entries);
        });
        std::sort(geometries.begin(), geometries.end(),
                  [](const Geometry& a, const Geometry& b) { return a.worst < b.worst; });
        const auto within20 = std::count_if(geometries.begin(), geometries.end(),
                                            [](const Geometry& g) { return g.worst <= 0.2; });
        std::printf(
            "%zu geometries (matched pairs of ideal prisms, %s, ior %.2f, roughness %g, %llu "
            "rays per entrance and rotation) against %s: %ld within 20%% at every entry\n",
            geometries.size(), full ? "full-cube arrays" : "truncated cubes", kEta, roughness,
            static_cast<unsigned long long>(rays), table.file.c_str(), long(within20));
        std::printf("\n%6s %17s %7s %7s  scaled / measured per entry\n", "cant", "errors (arcmin)",
                    "worst", "fewest");
        for (size_t i = 0; i < std::min<size_t>(10, geometries.size()); ++i) {
            const Geometry& g = geometries[i];
            std::printf("%6.1f %5.1f %5.1f %5.1f %6.1f%% %7llu ", g.cant, g.errors[0], g.errors[1],
                        g.errors[2], 100.0 * g.worst, static_cast<unsigned long long>(g.fewest));
            for (size_t e = 0; e < table.entries.size(); ++e)
                std::printf(" %5.2f", g.scale * g.ra[e] / table.entries[e].ra);
            std::printf("\n");
        }
        std::printf("\nentries:");
        for (const RaEntry& e : table.entries)
            std::printf(" (%g, %g)", e.observation_deg, e.entrance_deg);
        std::printf(" (observation, entrance in degrees)\n");
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "retroprism_geometry_scan: %s\n", e.what());
        return 1;
    }
}
