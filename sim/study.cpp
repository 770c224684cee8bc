// study.cpp: the accuracy study's runs and metrics (see study.h).
#include "study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <thread>

#include "error.h"

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
// counting the exits in every cone B (Q(A, B) / Omega_p(A)); the pairs a < b.
std::vector<RecipPair> reciprocity_runs(double alpha, double eta, int prism, std::uint64_t rays,
                                        std::uint64_t seed, int threads,
                                        const StudyObserver& observer, StudyResults& out) {
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
        out.simSeconds += run.seconds;
        out.simRays += double(run.tally.rays);
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
    std::vector<RecipPair> pairs;
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
            pairs.push_back(p);
        }
    return pairs;
}

// The relative asymmetry |x - y| / mean, appended when the pair is not zero.
void add_asymmetry(std::vector<double>& out, double x, double y) {
    if (x + y > 1e-12) out.push_back(std::abs(x - y) / (0.5 * (x + y)));
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

double StudyResults::diffuse_alpha() const {
    return options.quick ? grid.alphas[0] : kDiffuseAlpha;
}

const ConfigResult& StudyResults::at(double theta, double alpha, double eta, int prism) const {
    for (const ConfigResult& r : results)
        if (r.c.theta == theta && r.c.alpha == alpha && r.c.eta == eta && r.c.prism == prism)
            return r;
    throw InputError("accuracy study: no configuration " +
                     config_label(Config{theta, alpha, eta, prism}));
}

StudyResults run_study(const StudyOptions& so, const StudyObserver& observer) {
    StudyResults out;
    out.options = so;
    out.grid = study_grid(so.quick);
    out.machine = machine_description();
    out.date = today();
    const StudyGrid& g = out.grid;
    auto progress = [&](const std::string& label) {
        return observer.progress ? observer.progress(label) : RunOptions::Progress();
    };
    const auto t0 = std::chrono::steady_clock::now();
    const std::string loadStart = load_average();
    std::uint64_t k = 0;
    for (double eta : g.etas)
        for (int prism : g.prisms)
            for (double alpha : g.alphas)
                for (double theta : g.thetas) {
                    const Config c{theta, alpha, eta, prism};
                    const std::string label = fmt("[%.0f/", double(out.results.size() + 1)) +
                                              fmt("%.0f] ", double(g.size())) + config_label(c);
                    out.results.push_back(run_config(c, so.rays, so.seed + k++, true, true,
                                                     so.threads, progress(label)));
                    const ConfigResult& r = out.results.back();
                    out.simSeconds += r.sim.seconds;
                    out.simRays += double(r.sim.rays);
                    out.threadsUsed = r.sim.threads;
                    if (observer.config_done) observer.config_done(r);
                }
    // The paper's way up (substrate light straight to the top surface), for the diffuse lobe.
    for (double eta : g.etas)
        for (int prism : g.prisms)
            for (double theta : g.thetas) {
                const Config c{theta, out.diffuse_alpha(), eta, prism};
                out.direct.push_back(run_config(c, so.diffuseRays, so.seed + 100000 + k++, false,
                                                false, so.threads,
                                                progress("[way up direct] " + config_label(c))));
                out.simSeconds += out.direct.back().sim.seconds;
                out.simRays += double(out.direct.back().sim.rays);
            }
    // Reciprocity: cone-to-cone runs for every material.
    std::uint64_t m = 0;
    for (double eta : g.etas)
        for (int prism : g.prisms)
            for (double alpha : g.alphas) {
                const std::vector<RecipPair> rp =
                    reciprocity_runs(alpha, eta, prism, so.recipRays, so.seed + 200000 + 100 * m++,
                                     so.threads, observer, out);
                out.pairs.insert(out.pairs.end(), rp.begin(), rp.end());
            }
    out.elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.machine += "; 1-minute load average " + loadStart + " at the start and " + load_average() +
                   " at the end of the simulations (above the number of hardware threads, "
                   "other processes shared the cores and the rays/s below are lower than on an "
                   "idle machine)";
    return out;
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
