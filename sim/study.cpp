// study.cpp: the accuracy study's runs and metrics (see study.h).
#include "study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <thread>

#include "error.h"
#include "parse.h"

namespace retroprism::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

std::string fmt(const char* f, double v) {
    char buf[128];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// Total f of a cell: surface + retro + diffuse, binomial (the categories are exclusive).
Estimate total_estimate(const Tally& t, int grid, int cell, double projected) {
    const std::uint64_t* c = &t.counts[size_t(grid)][size_t(cell) * kChannels];
    Estimate e = fraction(c[kSurface] + c[kRetro] + c[kDiffuse], t.rays);
    if (!(projected > 0)) return Estimate();
    e.value /= projected;
    e.se /= projected;
    return e;
}

// Minimum subdivision of a cell per grid for the cell integrals.
int min_subdivision(int g) {
    return g == kGridHemi ? 3 : g >= kGridNormal ? 12 : 4;
}

// What run_config's simulation and its variants share: the grids, the cells' measures, the
// retro peak's cells and the lobe fit's cell selection.
struct Cells {
    dvec3 wi;
    std::vector<Grid> grids;
    std::vector<Feature> features;
    std::vector<CellIntegrals> meas;
    std::vector<int> centre;    // the 3 x 3 cells of the retro grid about wi
    std::vector<double> weight; // the fit's weights: the simulated counts
    std::vector<char> use;      // the fit's cells
};

// The simulation's side of a configuration: peak, energies, diffuse levels, fates, the lobe fit,
// the noise floors of the L1 errors and the cross-sections.
void measure_simulation(const Tally& t, Cells& cells, SimResult& s) {
    const std::vector<Grid>& grids = cells.grids;
    const std::vector<CellIntegrals>& meas = cells.meas;
    const double n = double(t.rays);
    const Grid& rg = grids[kGridRetro];
    s.hx = rg.x1;
    s.hy = rg.y1;
    // The retro peak: the 3 x 3 cells about wi (the grid's centre cell is centred on wi).
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
            cells.centre.push_back((rg.ny / 2 + dj) * rg.nx + rg.nx / 2 + di);
    {
        std::uint64_t cnt = 0;
        double proj = 0;
        for (int c : cells.centre) {
            cnt += t.counts[kGridRetro][size_t(c) * kChannels + kRetro];
            proj += meas[kGridRetro].projected[size_t(c)];
        }
        s.peak = fraction(cnt, t.rays);
        s.peak.value /= proj;
        s.peak.se /= proj;
    }
    s.energy = fraction(t.fates[kFateRetro], t.rays);
    s.energyPrimary = fraction(t.retro_primary, t.rays);
    s.energyMultiple = fraction(t.retro_multiple, t.rays);
    s.diffuseNormal = cell_brdf(t, kGridNormal, 0, kDiffuse, meas[kGridNormal].projected[0]);
    s.diffuse60 = cell_brdf(t, kGridD60, 0, kDiffuse, meas[kGridD60].projected[0]);
    s.diffuseAlbedo = fraction(t.fates[kFateDiffuse], t.rays);
    s.surface = fraction(t.fates[kFateSurface], t.rays);
    s.surfaceSingle = fraction(t.surface_single, t.rays);
    s.absorbed = fraction(t.fates[kFateAbsorbedSubstrate] + t.fates[kFateAbsorbedFaces], t.rays);
    s.trapped = t.fates[kFateTrapped];

    // The fit's cells: enough counts, within e^-3 of the peak, mostly above the horizon.
    const int nCells = rg.cells();
    const double fullArea = (rg.x1 - rg.x0) * (rg.y1 - rg.y0) / nCells;
    std::vector<double> density(size_t(nCells), 0.0);
    cells.weight.assign(size_t(nCells), 0.0);
    cells.use.assign(size_t(nCells), 0);
    double peakCount = 0;
    for (int c = 0; c < nCells; ++c)
        peakCount =
            std::max(peakCount, double(t.counts[kGridRetro][size_t(c) * kChannels + kRetro]));
    for (int c = 0; c < nCells; ++c) {
        const double cnt = double(t.counts[kGridRetro][size_t(c) * kChannels + kRetro]);
        const double area = meas[kGridRetro].param_area[size_t(c)];
        density[size_t(c)] = area > 0 ? cnt / area : 0;
        cells.weight[size_t(c)] = cnt;
        cells.use[size_t(c)] =
            cnt >= 16 && cnt >= std::exp(-3.0) * peakCount && area >= 0.5 * fullArea;
    }
    s.fit = fit_lobe(rg, density, cells.weight, cells.use);

    // Noise floors of the L1 errors: the mean absolute deviation of each cell's estimate.
    auto noise = [&](int g, bool retroOnly) {
        double sum = 0, mass = 0;
        for (int c = 0; c < grids[size_t(g)].cells(); ++c) {
            const std::uint64_t* k = &t.counts[size_t(g)][size_t(c) * kChannels];
            const double p =
                double(retroOnly ? k[kRetro] : k[kSurface] + k[kRetro] + k[kDiffuse]) / n;
            sum += std::sqrt(2.0 / kPi) * std::sqrt(std::max(0.0, p * (1 - p)) / n);
            mass += p;
        }
        return mass > 0 ? sum / mass : 0.0;
    };
    s.l1Noise = noise(kGridHemi, false);
    s.l1RetroNoise = noise(kGridRetro, true);

    // Cross-sections of the retro lobe and the in-plane strip.
    const int midRow = rg.ny / 2, midCol = rg.nx / 2;
    for (int i = 0; i < rg.nx; ++i) {
        const int c = midRow * rg.nx + i;
        s.rowX.push_back(std::atan(rg.x0 + (i + 0.5) * (rg.x1 - rg.x0) / rg.nx) / kDeg);
        s.row.push_back(cell_brdf(t, kGridRetro, c, kRetro, meas[kGridRetro].projected[size_t(c)]));
    }
    for (int j = 0; j < rg.ny; ++j) {
        const int c = j * rg.nx + midCol;
        s.colX.push_back(std::atan(rg.y0 + (j + 0.5) * (rg.y1 - rg.y0) / rg.ny) / kDeg);
        s.col.push_back(cell_brdf(t, kGridRetro, c, kRetro, meas[kGridRetro].projected[size_t(c)]));
    }
    const Grid& sg = grids[kGridInPlane];
    for (int i = 0; i < sg.nx; ++i) {
        const double proj = meas[kGridInPlane].projected[size_t(i)];
        s.stripX.push_back((sg.x0 + (i + 0.5) * (sg.x1 - sg.x0) / sg.nx) / kDeg);
        s.strip[0].push_back(cell_brdf(t, kGridInPlane, i, kSurface, proj));
        s.strip[1].push_back(cell_brdf(t, kGridInPlane, i, kRetro, proj));
        s.strip[2].push_back(cell_brdf(t, kGridInPlane, i, kDiffuse, proj));
        s.strip[3].push_back(total_estimate(t, kGridInPlane, i, proj));
    }
}

// Variant `v`'s side of a configuration: the same quantities from the analytic BRDF integrated
// over the same cells, and its L1 errors against the simulation.
VariantResult measure_variant(const Config& cfg, int v, const Tally& t, const Cells& cells,
                              int threads) {
    VariantResult r;
    const std::vector<Grid>& grids = cells.grids;
    const Grid& rg = grids[kGridRetro];
    const double n = double(t.rays);
    const Params p = config_params(cfg, v);
    f64::rp_material m = prepare_material(sanitize(p));
    f64::rp_incident si;
    f64::rp_incident_setup(m, cells.wi, si);
    r.alphaPar = si.alphaPar;
    r.alphaPerp = si.alphaPerp;
    const CellFunction f = model_function(p, cells.wi);
    auto integ = [&](int g) {
        return integrate_cells(grids[size_t(g)], 3, f, cells.features, min_subdivision(g), 64,
                               threads);
    };
    const CellIntegrals ciR = integ(kGridRetro), ciH = integ(kGridHemi), ciS = integ(kGridInPlane),
                        ciN = integ(kGridNormal), ciD = integ(kGridD60);
    {
        double e = 0, proj = 0;
        for (int c : cells.centre) {
            e += ciR.values[size_t(c) * 3 + 1];
            proj += ciR.projected[size_t(c)];
        }
        r.peak = e / proj;
    }
    const int nCells = rg.cells();
    std::vector<double> da(size_t(nCells), 0.0);
    for (int c = 0; c < nCells; ++c) {
        const double area = ciR.param_area[size_t(c)];
        da[size_t(c)] = area > 0 ? ciR.values[size_t(c) * 3 + 1] * n / area : 0;
    }
    r.fit = fit_lobe(rg, da, cells.weight, cells.use);
    double l1 = 0, mass = 0;
    for (int c = 0; c < grids[kGridHemi].cells(); ++c) {
        const double* a = &ciH.values[size_t(c) * 3];
        r.surface += a[0];
        r.energy += a[1];
        r.diffuseAlbedo += a[2];
        const std::uint64_t* k = &t.counts[kGridHemi][size_t(c) * kChannels];
        const double es = double(k[kSurface] + k[kRetro] + k[kDiffuse]) / n;
        l1 += std::abs(a[0] + a[1] + a[2] - es);
        mass += es;
    }
    r.l1 = mass > 0 ? l1 / mass : 0;
    double l1r = 0, massR = 0;
    for (int c = 0; c < nCells; ++c) {
        const double es = double(t.counts[kGridRetro][size_t(c) * kChannels + kRetro]) / n;
        l1r += std::abs(ciR.values[size_t(c) * 3 + 1] - es);
        massR += es;
    }
    r.l1Retro = massR > 0 ? l1r / massR : 0;
    r.diffuseNormal = ciN.values[2] / ciN.projected[0];
    r.diffuse60 = ciD.values[2] / ciD.projected[0];
    const int midRow = rg.ny / 2, midCol = rg.nx / 2;
    for (int i = 0; i < rg.nx; ++i) {
        const int c = midRow * rg.nx + i;
        r.row.push_back(ciR.values[size_t(c) * 3 + 1] / ciR.projected[size_t(c)]);
    }
    for (int j = 0; j < rg.ny; ++j) {
        const int c = j * rg.nx + midCol;
        r.col.push_back(ciR.values[size_t(c) * 3 + 1] / ciR.projected[size_t(c)]);
    }
    const Grid& sg = grids[kGridInPlane];
    for (int i = 0; i < sg.nx; ++i) {
        const double proj = ciS.projected[size_t(i)];
        double tot = 0;
        for (int l = 0; l < 3; ++l) {
            const double val = proj > 0 ? ciS.values[size_t(i) * 3 + size_t(l)] / proj : 0;
            r.strip[size_t(l)].push_back(val);
            tot += val;
        }
        r.strip[3].push_back(tot);
    }
    return r;
}

std::string machine_description() {
    std::ifstream cpu("/proc/cpuinfo");
    std::string line, model;
    while (std::getline(cpu, line))
        if (line.rfind("model name", 0) == 0) {
            model = line.substr(line.find(':') + 2);
            break;
        }
    const unsigned hc = std::thread::hardware_concurrency();
    return (model.empty() ? std::string("unknown CPU") : model) + ", " + std::to_string(hc) +
           " hardware threads, compiler " +
#ifdef __clang__
           std::string("clang ") +
#else
           std::string("GCC ") +
#endif
           __VERSION__ +
#ifdef NDEBUG
           ", release build (NDEBUG)";
#else
           ", debug build";
#endif
}

// The 1-minute load average (/proc/loadavg), or "?".
std::string load_average() {
    std::ifstream in("/proc/loadavg");
    std::string v;
    if (!(in >> v)) return "?";
    return v;
}

std::string today() {
    std::time_t now = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%d", std::gmtime(&now));
    return buf;
}

// Cone-to-cone runs of one material: for each probe cone A, a run with incidence spread over A
// counting the exits in every cone B (Q(A, B) / Omega_p(A)); the pairs a < b go to unit.pairs,
// the rays and seconds to unit's, the most threads a run used to threadsUsed.
void reciprocity_runs(double alpha, double eta, int prism, std::uint64_t rays, std::uint64_t seed,
                      int threads, const StudyObserver& observer, UnitResult& unit,
                      int& threadsUsed) {
    const std::vector<ProbeDir> dirs = probe_dirs();
    const double r = kRecipConeDeg * kDeg;
    const Sheet sheet = sheet_from_params(config_params(Config{0, alpha, eta, prism}, 0), 0);
    std::vector<Grid> cones;
    for (const ProbeDir& d : dirs)
        cones.push_back(cone_grid("cone", direction_deg(d.theta, d.phi), r));
    std::vector<std::vector<Estimate>> q(dirs.size(), std::vector<Estimate>(dirs.size()));
    for (size_t a = 0; a < dirs.size(); ++a) {
        RunOptions opt;
        opt.rays = rays;
        opt.seed = seed + a;
        opt.threads = threads;
        opt.incidence_cone = r;
        if (observer.progress)
            opt.progress = observer.progress("[reciprocity] " + material_key(alpha, eta, prism) +
                                             fmt(" from theta %g", dirs[a].theta) +
                                             fmt(" phi %g", dirs[a].phi));
        const dvec3 wa = direction_deg(dirs[a].theta, dirs[a].phi);
        const Run run = simulate(sheet, wa, cones, opt);
        unit.seconds += run.seconds;
        unit.rays += run.tally.rays;
        threadsUsed = std::max(threadsUsed, run.threads);
        // Omega_p(A) = pi sin^2 r cos(theta_A) for a cone above the horizon.
        const double projA = kPi * std::sin(r) * std::sin(r) * wa.z;
        for (size_t b = 0; b < dirs.size(); ++b) {
            const std::uint64_t* k = &run.tally.counts[b][0];
            Estimate e = fraction(k[kSurface] + k[kRetro] + k[kDiffuse], run.tally.rays);
            e.value *= projA;
            e.se *= projA;
            q[a][b] = e;
        }
    }
    for (size_t a = 0; a < dirs.size(); ++a)
        for (size_t b = a + 1; b < dirs.size(); ++b) {
            RecipPair p;
            p.alpha = alpha;
            p.eta = eta;
            p.prism = prism;
            p.a = int(a);
            p.b = int(b);
            p.qab = q[a][b];
            p.qba = q[b][a];
            unit.pairs.push_back(p);
        }
}

// The relative asymmetry |x - y| / mean, appended when the pair is not zero.
void add_asymmetry(std::vector<double>& out, double x, double y) {
    if (x + y > 1e-12) out.push_back(std::abs(x - y) / (0.5 * (x + y)));
}

// Runs unit `index` of `units` (study_units(so)), of `configs` configurations.
UnitResult run_unit(const std::vector<StudyUnit>& units, size_t index, size_t configs,
                    const StudyOptions& so, const StudyObserver& observer, int& threadsUsed) {
    const StudyUnit& u = units[index];
    UnitResult out;
    out.index = index;
    auto progress = [&](const std::string& label) {
        return observer.progress ? observer.progress(label) : RunOptions::Progress();
    };
    if (u.kind == UnitKind::Reciprocity) {
        reciprocity_runs(u.c.alpha, u.c.eta, u.c.prism, so.recipRays, u.seed, so.threads, observer,
                         out, threadsUsed);
        return out;
    }
    const bool config = u.kind == UnitKind::Config;
    // Config: the simulator's reciprocal way up, and the variants; Direct: the paper's way up
    // (substrate light straight to the top surface), for the diffuse lobe.
    const std::string label = config ? fmt("[%.0f/", double(index + 1)) +
                                           fmt("%.0f] ", double(configs)) + config_label(u.c)
                                     : "[way up direct] " + config_label(u.c);
    out.config = run_config(u.c, u.rays, u.seed, config, config, so.threads, progress(label));
    out.rays = out.config.sim.rays;
    out.seconds = out.config.sim.seconds;
    threadsUsed = std::max(threadsUsed, out.config.sim.threads);
    if (config && observer.config_done) observer.config_done(out.config);
    return out;
}

std::string shard_text(ShardSpec s) {
    return fmt("%.0f/", s.k) + fmt("%.0f", s.n);
}

// A shard as the merge's errors name it: its file.
std::string shard_name(const StudyShard& p) {
    return p.source.empty() ? "shard " + shard_text(p.shard) : p.source;
}

// The options that make a study, as the command line gives them.
std::string options_text(const StudyOptions& o) {
    return "--rays " + std::to_string(o.rays) + " --diffuse-rays " + std::to_string(o.diffuseRays) +
           " --recip-rays " + std::to_string(o.recipRays) + " --seed " + std::to_string(o.seed) +
           (o.quick ? " --quick" : "");
}

std::string unit_label(const StudyUnit& u) {
    return u.kind == UnitKind::Config ? "configuration " + config_label(u.c)
           : u.kind == UnitKind::Direct
               ? "way-up-direct configuration " + config_label(u.c)
               : "reciprocity runs of " + material_key(u.c.alpha, u.c.eta, u.c.prism);
}

// Whether a unit's results are those of unit u: its configuration, or its material's pairs.
bool unit_matches(const UnitResult& r, const StudyUnit& u) {
    const Config& c = r.config.c;
    if (u.kind != UnitKind::Reciprocity)
        return c.theta == u.c.theta && c.alpha == u.c.alpha && c.eta == u.c.eta &&
               c.prism == u.c.prism && r.pairs.empty();
    const size_t dirs = probe_dirs().size();
    if (r.pairs.size() != dirs * (dirs - 1) / 2) return false;
    for (const RecipPair& p : r.pairs)
        if (p.alpha != u.c.alpha || p.eta != u.c.eta || p.prism != u.c.prism) return false;
    return true;
}

// Shard p holds exactly its own units (owner: shard_assignment), each with its unit's results.
void check_shard_units(const StudyShard& p, const std::vector<StudyUnit>& units,
                       const std::vector<int>& owner) {
    std::vector<size_t> own;
    for (size_t i = 0; i < units.size(); ++i)
        if (owner[i] == p.shard.k) own.push_back(i);
    for (size_t j = 0; j < std::max(own.size(), p.units.size()); ++j) {
        const size_t held = j < p.units.size() ? p.units[j].index : units.size();
        if (j < p.units.size() && held >= units.size())
            throw InputError(shard_name(p) + ": unit " + std::to_string(held) + ", of a study of " +
                             std::to_string(units.size()) + " units");
        const size_t want = j < own.size() ? own[j] : units.size();
        if (held < want)
            throw InputError(shard_name(p) + ": shard " + shard_text(p.shard) + " holds unit " +
                             std::to_string(held) + " (" + unit_label(units[held]) +
                             "), which is shard " + shard_text({owner[held], p.shard.n}) + "'s");
        if (held > want)
            throw InputError(shard_name(p) + ": shard " + shard_text(p.shard) + " lacks its unit " +
                             std::to_string(want) + " (" + unit_label(units[want]) + ")");
        if (!unit_matches(p.units[j], units[want]))
            throw InputError(shard_name(p) + ": unit " + std::to_string(want) +
                             " does not hold the results of its " + unit_label(units[want]));
    }
}

// The shards of merge_study_shards by K (InputError naming the offending file unless they are
// all N shards of one study, each once, each holding its own units).
std::vector<const StudyShard*> shards_by_k(const std::vector<StudyShard>& parts,
                                           const std::vector<StudyUnit>& units) {
    const StudyShard& first = parts[0];
    const int n = first.shard.n;
    std::vector<const StudyShard*> byK(size_t(std::max(n, 0)), nullptr);
    for (const StudyShard& p : parts) {
        if (options_text(p.options) != options_text(first.options))
            throw InputError(shard_name(p) + ": a shard of another study (" +
                             options_text(p.options) + "; " + shard_name(first) + ": " +
                             options_text(first.options) + ")");
        if (p.shard.n != n || p.shard.k < 1 || p.shard.k > n)
            throw InputError(shard_name(p) + ": shard " + shard_text(p.shard) + ", but " +
                             shard_name(first) + " is one of " + fmt("%.0f", n) + " shards");
        const StudyShard*& slot = byK[size_t(p.shard.k - 1)];
        if (slot)
            throw InputError(shard_name(p) + ": shard " + shard_text(p.shard) + " again (" +
                             shard_name(*slot) + " is shard " + shard_text(p.shard) + ")");
        slot = &p;
    }
    std::string given;
    for (const StudyShard* p : byK)
        if (p) given += (given.empty() ? "" : ", ") + shard_name(*p) + " " + shard_text(p->shard);
    for (int k = 1; k <= n; ++k)
        if (!byK[size_t(k - 1)])
            throw InputError("merging shards: shard " + shard_text({k, n}) +
                             " is missing (given: " + given + ")");
    const std::vector<int> owner = shard_assignment(units, n);
    for (const StudyShard* p : byK)
        check_shard_units(*p, units, owner);
    return byK;
}

} // namespace

StudyGrid study_grid(bool quick) {
    if (quick) return {{20, 60}, {0.1}, {1.49}, {f64::RP_PRISM_TIR}};
    return {{0, 20, 40, 60, 75, 85},
            {0.005, 0.02, 0.1, 0.3},
            {1.49, 1.586},
            {f64::RP_PRISM_TIR, f64::RP_PRISM_METALLIZED}};
}

const char* prism_name(int prism) {
    return prism == f64::RP_PRISM_TIR          ? "tir"
           : prism == f64::RP_PRISM_METALLIZED ? "metallized"
                                               : "ideal";
}

int prism_of_name(const std::string& name) {
    for (int p : {f64::RP_PRISM_IDEAL, f64::RP_PRISM_TIR, f64::RP_PRISM_METALLIZED})
        if (name == prism_name(p)) return p;
    return -1;
}

std::string config_label(const Config& c) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%g deg, alpha %g, eta %g, %s", c.theta, c.alpha, c.eta,
                  prism_name(c.prism));
    return buf;
}

std::string material_key(double alpha, double eta, int prism) {
    return fmt("%g", alpha) + "/" + fmt("%g", eta) + "/" + prism_name(prism);
}

Params config_params(const Config& c, int variant) {
    Params p;
    p.roughness = c.alpha;
    p.ior = c.eta;
    p.prism_reflection = c.prism;
    p.diffuse_color = {kStudyKd, kStudyKd, kStudyKd};
    p.retro_lobe = kVariants[variant].aniso;
    p.reciprocal = kVariants[variant].recip != 0;
    return p;
}

dvec3 direction_deg(double thetaDeg, double phiDeg) {
    const double t = thetaDeg * kDeg, p = phiDeg * kDeg;
    return dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

ConfigResult run_config(const Config& cfg, std::uint64_t rays, std::uint64_t seed,
                        bool throughPrisms, bool analytic, int threads,
                        const RunOptions::Progress& progress) {
    ConfigResult out;
    out.c = cfg;
    Cells cells;
    cells.wi = direction_deg(cfg.theta, 0);
    const dvec3 wi = cells.wi, wr(-wi.x, -wi.y, wi.z);
    Sheet sheet = sheet_from_params(config_params(cfg, 0), 0);
    sheet.upward_through_prisms = throughPrisms;
    cells.grids = standard_grids(sheet, wi);
    cells.grids.push_back(cone_grid("normal", dvec3(0, 0, 1), kDiffuseConeDeg * kDeg));
    cells.grids.push_back(cone_grid("d60", direction_deg(60, 90), kDiffuseConeDeg * kDeg));

    RunOptions opt;
    opt.rays = rays;
    opt.seed = seed;
    opt.threads = threads;
    opt.progress = progress;
    const Run run = simulate(sheet, wi, cells.grids, opt);
    out.sim.rays = run.tally.rays;
    out.sim.seconds = run.seconds;
    out.sim.threads = run.threads;

    // The cells' measures, with the quadrature the analytic integrals use (the same features).
    f64::rp_material ma = prepare_material(sanitize(config_params(cfg, 1)));
    f64::rp_incident sa;
    f64::rp_incident_setup(ma, wi, sa);
    cells.features = {{wi, sa.alphaPerp}, {wr, sheet.alpha}};
    cells.meas.resize(cells.grids.size());
    for (size_t g = 0; g < cells.grids.size(); ++g)
        cells.meas[g] = integrate_cells(cells.grids[g], 0, nullptr, cells.features,
                                        min_subdivision(int(g)), 64, threads);
    measure_simulation(run.tally, cells, out.sim);
    if (!analytic) return out;
    for (int v = 0; v < 4; ++v)
        out.v[size_t(v)] = measure_variant(cfg, v, run.tally, cells, threads);
    return out;
}

std::vector<ProbeDir> probe_dirs() {
    std::vector<ProbeDir> out;
    for (double t : study_grid(false).thetas)
        for (double ph : {0.0, 180.0})
            if (t > 0 || ph == 0) out.push_back({t, ph});
    return out;
}

double reciprocity_z(const RecipPair& q, std::uint64_t rays) {
    const std::vector<ProbeDir> dirs = probe_dirs();
    const double r = kRecipConeDeg * kDeg;
    const double oa = kPi * std::sin(r) * std::sin(r) * direction_deg(dirs[size_t(q.a)].theta, 0).z;
    const double ob = kPi * std::sin(r) * std::sin(r) * direction_deg(dirs[size_t(q.b)].theta, 0).z;
    const double mean = 0.5 * (q.qab.value + q.qba.value);
    const double n = double(rays);
    const double var = (oa * mean * (1 - mean / oa) + ob * mean * (1 - mean / ob)) / n;
    return var > 0 ? (q.qab.value - q.qba.value) / std::sqrt(var) : 0.0;
}

double diffuse_alpha(bool quick) {
    return quick ? study_grid(true).alphas[0] : kDiffuseAlpha;
}

double StudyResults::diffuse_alpha() const {
    return sim::diffuse_alpha(options.quick);
}

const ConfigResult& StudyResults::at(double theta, double alpha, double eta, int prism) const {
    for (const ConfigResult& r : results)
        if (r.c.theta == theta && r.c.alpha == alpha && r.c.eta == eta && r.c.prism == prism)
            return r;
    throw InputError("accuracy study: no configuration " +
                     config_label(Config{theta, alpha, eta, prism}));
}

StudyResults without_metadata(StudyResults s) {
    s.machine.clear();
    s.date.clear();
    s.simSeconds = s.elapsed = 0;
    s.threadsUsed = 0;
    for (auto* list : {&s.results, &s.direct})
        for (ConfigResult& r : *list) {
            r.sim.seconds = 0;
            r.sim.threads = 0;
        }
    return s;
}

std::vector<StudyUnit> study_units(const StudyOptions& so) {
    const StudyGrid g = study_grid(so.quick);
    std::vector<StudyUnit> units;
    for (double eta : g.etas)
        for (int prism : g.prisms)
            for (double alpha : g.alphas)
                for (double theta : g.thetas)
                    units.push_back({UnitKind::Config, Config{theta, alpha, eta, prism},
                                     so.seed + units.size(), so.rays});
    for (double eta : g.etas)
        for (int prism : g.prisms)
            for (double theta : g.thetas)
                units.push_back({UnitKind::Direct,
                                 Config{theta, diffuse_alpha(so.quick), eta, prism},
                                 so.seed + 100000 + units.size(), so.diffuseRays});
    std::uint64_t m = 0;
    for (double eta : g.etas)
        for (int prism : g.prisms)
            for (double alpha : g.alphas)
                units.push_back({UnitKind::Reciprocity, Config{0, alpha, eta, prism},
                                 so.seed + 200000 + 100 * m++, so.recipRays * probe_dirs().size()});
    return units;
}

ShardSpec parse_shard(const std::string& text, const std::string& what, size_t units) {
    const size_t slash = text.find('/');
    const std::string range =
        "expected K/N, whole numbers with 1 <= K <= N <= " + std::to_string(units) +
        " (the study's work units)";
    const auto part = [&](const std::string& t) {
        const std::optional<double> v = try_parse_number(t);
        if (!v || *v != std::floor(*v) || *v < 1 || *v > double(units))
            throw InputError(what + " " + text + ": " + range);
        return int(*v);
    };
    if (slash == std::string::npos) throw InputError(what + " " + text + ": " + range);
    const ShardSpec s{part(text.substr(0, slash)), part(text.substr(slash + 1))};
    if (s.k > s.n) throw InputError(what + " " + text + ": " + range);
    return s;
}

std::vector<int> shard_assignment(const std::vector<StudyUnit>& units, int n) {
    std::vector<size_t> order(units.size());
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return units[a].rays > units[b].rays; });
    std::vector<std::uint64_t> load(size_t(std::max(n, 1)), 0);
    std::vector<int> shard(units.size(), 1);
    for (size_t i : order) {
        const size_t k = size_t(std::min_element(load.begin(), load.end()) - load.begin());
        load[k] += units[i].rays;
        shard[i] = int(k) + 1;
    }
    return shard;
}

StudyShard run_study_shard(const StudyOptions& so, ShardSpec shard, const StudyObserver& observer) {
    StudyShard out;
    out.options = so;
    out.shard = shard;
    out.machine = machine_description();
    out.date = today();
    const auto t0 = std::chrono::steady_clock::now();
    const std::string loadStart = load_average();
    const std::vector<StudyUnit> units = study_units(so);
    const std::vector<int> owner = shard_assignment(units, shard.n);
    const size_t configs = study_grid(so.quick).size();
    int threadsUsed = 1;
    for (size_t i = 0; i < units.size(); ++i)
        if (owner[i] == shard.k) {
            out.units.push_back(run_unit(units, i, configs, so, observer, threadsUsed));
            out.simSeconds += out.units.back().seconds;
        }
    out.threadsUsed = threadsUsed;
    out.elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string loadEnd = load_average();
    // Other processes: load before the study's threads started, or more at its end than the
    // study's own threads on the machine's hardware threads account for.
    const double hardware = std::max(1u, std::thread::hardware_concurrency());
    const bool shared =
        std::atof(loadStart.c_str()) > 0.5 || std::atof(loadEnd.c_str()) > hardware + 0.5;
    out.machine += "; 1-minute load average " + loadStart + " at the start and " + loadEnd +
                   " at the end of the simulations" +
                   (shared ? " (other processes shared the cores: the rays/s below are lower "
                             "than on an idle machine)"
                           : " (the end figure counts the study's own threads)");
    return out;
}

StudyResults merge_study_shards(const std::vector<StudyShard>& parts) {
    if (parts.empty()) throw InputError("merging shards: no shards given");
    const std::vector<StudyUnit> units = study_units(parts[0].options);
    const std::vector<const StudyShard*> byK = shards_by_k(parts, units);
    StudyResults out;
    out.options = parts[0].options;
    out.grid = study_grid(out.options.quick);
    std::vector<const UnitResult*> byIndex(units.size());
    for (const StudyShard* p : byK)
        for (const UnitResult& u : p->units)
            byIndex[u.index] = &u;
    for (size_t i = 0; i < units.size(); ++i) {
        const UnitResult& u = *byIndex[i];
        out.simRays += double(u.rays);
        out.simSeconds += u.seconds;
        if (units[i].kind == UnitKind::Config) out.results.push_back(u.config);
        if (units[i].kind == UnitKind::Direct) out.direct.push_back(u.config);
        out.pairs.insert(out.pairs.end(), u.pairs.begin(), u.pairs.end());
    }
    std::string firstDate = byK[0]->date, lastDate = firstDate;
    for (const StudyShard* p : byK) {
        out.elapsed = std::max(out.elapsed, p->elapsed);
        out.threadsUsed = std::max(out.threadsUsed, p->threadsUsed);
        const std::string which = byK.size() > 1 ? "shard " + shard_text(p->shard) + ": " : "";
        out.machine += (out.machine.empty() ? "" : "; ") + which + p->machine;
        firstDate = std::min(firstDate, p->date);
        lastDate = std::max(lastDate, p->date);
    }
    out.date = firstDate == lastDate ? firstDate : firstDate + " to " + lastDate;
    return out;
}

StudyResults run_study(const StudyOptions& so, const StudyObserver& observer) {
    return merge_study_shards({run_study_shard(so, ShardSpec{1, 1}, observer)});
}

Reciprocity analyse_reciprocity(const StudyResults& s) {
    Reciprocity rec;
    const std::vector<ProbeDir> dirs = probe_dirs();
    for (const RecipPair& p : s.pairs) {
        if (!(p.qab.value + p.qba.value > 0)) continue;
        rec.z.push_back(reciprocity_z(p, s.options.recipRays));
        rec.rel.push_back((p.qab.value - p.qba.value) / (0.5 * (p.qab.value + p.qba.value)));
    }
    for (double eta : s.grid.etas)
        for (int prism : s.grid.prisms)
            for (double alpha : s.grid.alphas) {
                std::vector<PrismaticRetroreflector<double>> nodes;
                for (int v = 0; v < 4; ++v)
                    nodes.emplace_back(config_params(Config{0, alpha, eta, prism}, v));
                for (size_t a = 0; a < dirs.size(); ++a)
                    for (size_t b = a + 1; b < dirs.size(); ++b) {
                        const dvec3 wa = direction_deg(dirs[a].theta, dirs[a].phi);
                        const dvec3 wb = direction_deg(dirs[b].theta, dirs[b].phi);
                        for (int v = 0; v < 4; ++v)
                            add_asymmetry(rec.wide[size_t(v)],
                                          nodes[size_t(v)].eval(wa, wb).f.total().x,
                                          nodes[size_t(v)].eval(wb, wa).f.total().x);
                    }
                // Near the retro peak: wo = wi tilted by 0.5, 1 and 2 alpha_o.
                for (double theta : s.grid.thetas) {
                    const dvec3 wi = direction_deg(theta, 0);
                    dvec3 ePar, ePerp;
                    lobe_frame(wi, ePar, ePerp);
                    const double aIso = s.at(theta, alpha, eta, prism).v[0].alphaPar;
                    for (int v = 0; v < 4; ++v)
                        for (double d : {0.5, 1.0, 2.0})
                            for (const dvec3& e : {ePar, -ePar, ePerp}) {
                                const dvec3 wo = glm::normalize(wi + d * aIso * e);
                                if (wo.z < 0.02) continue;
                                add_asymmetry(rec.near[size_t(v)],
                                              nodes[size_t(v)].eval(wi, wo).f.total().x,
                                              nodes[size_t(v)].eval(wo, wi).f.total().x);
                            }
                }
            }
    return rec;
}

double rel_se(const Estimate& e) {
    return e.value > 0 ? e.se / e.value : 1e300;
}

bool width_resolved(const SimResult& s, bool par) {
    if (!s.fit.ok) return false;
    return par ? s.fit.se_ax / s.fit.ax <= kResolvedSe : s.fit.se_ay / s.fit.ay <= kResolvedSe;
}

double width_err(const ConfigResult& r, int v, bool par) {
    const VariantResult& a = r.v[size_t(v)];
    if (!a.fit.ok || !r.sim.fit.ok) return NAN;
    return par ? a.fit.ax / r.sim.fit.ax - 1 : a.fit.ay / r.sim.fit.ay - 1;
}

double energy_err(const ConfigResult& r, int v) {
    return r.v[size_t(v)].energy / r.sim.energy.value - 1;
}

void Worst::add(double v, bool resolved, const std::string& w) {
    if (!resolved || !std::isfinite(v)) {
        ++unresolved;
        return;
    }
    ++counted;
    if (!any || std::abs(v) > std::abs(value)) {
        value = v;
        where = w;
        any = true;
    }
}

double median_of(std::vector<double> v) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double max_abs(const std::vector<double>& v) {
    double m = 0;
    for (double x : v)
        m = std::max(m, std::abs(x));
    return v.empty() ? NAN : m;
}

double rms(const std::vector<double>& v) {
    double s = 0;
    for (double x : v)
        s += x * x;
    return v.empty() ? NAN : std::sqrt(s / double(v.size()));
}

} // namespace retroprism::sim
