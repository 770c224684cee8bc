// simulate.cpp: `retroprism simulate`, the microgeometry simulator (sim/microgeometry.h,
// MODEL.md section 6) as a command: the tabulated BRDF per lobe, with standard errors, for a set
// of incident directions, as EXR and JSON; and `retroprism simulate --study`, the accuracy study
// of the analytic model's variants against it, which regenerates docs/accuracy.md, its plots and
// results.csv (the second half of this file: run_study and its helpers).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/argparse.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "commands.h"
#include "microgeometry.h"
#include "query.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace retroprism {

int run_study(const std::vector<std::string>& args);

namespace {

using sim::dvec3;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

std::string fmt(const char* f, double v) {
    char buf[512];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// A double rounded to 7 significant digits, so that JSON prints it short.
double r7(double v) {
    if (!std::isfinite(v) || v == 0) return v;
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.7g", v);
    return std::strtod(buf, nullptr);
}

double parse_real(const std::string& text, const std::string& option) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw InputError(option + " " + text + ": expected a finite number");
    return v;
}

std::uint64_t parse_count(const std::string& text, const std::string& option, double lo,
                          double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v != std::floor(v) || v < lo || v > hi)
        throw InputError(option + " " + text + ": expected a whole number in [" + fmt("%.0f", lo) +
                         ", " + fmt("%.0f", hi) + "]");
    return std::uint64_t(v);
}

dvec3 direction_deg(double thetaDeg, double phiDeg) {
    const double t = thetaDeg * kDeg, p = phiDeg * kDeg;
    return dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

// A progress bar on a terminal (stderr), nothing otherwise.
class ProgressBar {
  public:
    explicit ProgressBar(std::string label)
        : label_(std::move(label)), tty_(isatty(fileno(stderr)) != 0),
          t0_(std::chrono::steady_clock::now()) {}
    void operator()(std::uint64_t done, std::uint64_t total) {
        if (!tty_ || total == 0) return;
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
        const int width = 30, fill = int(double(width) * double(done) / double(total));
        std::string bar(size_t(fill), '#');
        bar.resize(size_t(width), '.');
        std::fprintf(stderr, "\r%s [%s] %3.0f%%  %.3g rays/s   ", label_.c_str(), bar.c_str(),
                     100.0 * double(done) / double(total), s > 0 ? double(done) / s : 0.0);
        if (done >= total) std::fprintf(stderr, "\r%*s\r", int(label_.size()) + width + 40, "");
        std::fflush(stderr);
    }

  private:
    std::string label_;
    bool tty_;
    std::chrono::steady_clock::time_point t0_;
};

// The folder of an output prefix exists and is writable, before any work is done.
void check_prefix(const std::string& prefix) {
    if (prefix.empty()) throw InputError("--out: empty prefix");
    fs::path dir = fs::path(prefix).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw InputError("--out " + prefix + ": folder " + dir.string() + " does not exist");
    const fs::path probe = dir / (".retroprism-write-test" + std::to_string(getpid()));
    {
        std::ofstream f(probe);
        if (!f || !(f << "x") || (f.close(), !f)) {
            fs::remove(probe, ec);
            throw InputError("--out " + prefix + ": folder " + dir.string() + " is not writable");
        }
    }
    fs::remove(probe, ec);
}

// The simulated lobes of one incident direction, per colour channel.
const char* kOutLobes[5] = {"surface", "surface_single", "retro", "diffuse", "total"};

struct ChannelData {
    // [lobe][cell] per grid, value and standard error (cosine-weighted cell averages of f).
    std::vector<std::array<std::vector<double>, 5>> f, se;
};

void write_exr(const std::string& path, const std::vector<sim::Grid>& grids,
               const std::vector<std::vector<double>>& projected,
               const std::array<ChannelData, 3>& ch, const json& meta) {
    std::vector<OIIO::ImageSpec> specs;
    std::vector<std::vector<float>> pixels;
    for (size_t g = 0; g < grids.size(); ++g) {
        const sim::Grid& grid = grids[g];
        OIIO::ImageSpec spec(grid.nx, grid.ny, 31, OIIO::TypeDesc::FLOAT);
        spec.channelnames.clear();
        for (const char* lobe : kOutLobes)
            for (const char* c : {"R", "G", "B"})
                spec.channelnames.push_back(std::string(lobe) + "." + c);
        for (const char* lobe : kOutLobes)
            for (const char* c : {"R", "G", "B"})
                spec.channelnames.push_back(std::string(lobe) + "_se." + c);
        spec.channelnames.push_back("projected_solid_angle.Y");
        spec.attribute("oiio:subimagename", grid.name);
        spec.attribute("compression", "zip");
        spec.attribute("retroprism:quantity",
                       "per lobe: cosine-weighted cell average of the BRDF f [1/sr] and its "
                       "standard error (_se); projected_solid_angle [sr] of the cell above the "
                       "horizon");
        const char* kinds[4] = {"gnomonic", "disk", "strip", "cone"};
        spec.attribute("retroprism:grid", grid.name);
        spec.attribute("retroprism:grid_kind", kinds[grid.kind]);
        spec.attribute("retroprism:mapping",
                       "pixel (i, j), j counted from the bottom row, is cell j*nx+i of the "
                       "parameter rectangle [x0,x1]x[y0,y1] (see the JSON output)");
        float frame[9] = {float(grid.c.x),  float(grid.c.y),  float(grid.c.z),
                          float(grid.e1.x), float(grid.e1.y), float(grid.e1.z),
                          float(grid.e2.x), float(grid.e2.y), float(grid.e2.z)};
        spec.attribute("retroprism:frame_c_e1_e2", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 9), frame);
        float rect[4] = {float(grid.x0), float(grid.x1), float(grid.y0), float(grid.y1)};
        spec.attribute("retroprism:x0_x1_y0_y1", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 4), rect);
        spec.attribute("retroprism:run", meta.dump());
        std::vector<float> px(size_t(grid.nx) * size_t(grid.ny) * 31, 0.0f);
        for (int cell = 0; cell < grid.cells(); ++cell) {
            const int i = cell % grid.nx, j = cell / grid.nx;
            float* p = &px[(size_t(grid.ny - 1 - j) * size_t(grid.nx) + size_t(i)) * 31];
            for (int l = 0; l < 5; ++l)
                for (int c = 0; c < 3; ++c) {
                    p[l * 3 + c] = float(ch[size_t(c)].f[g][size_t(l)][size_t(cell)]);
                    p[15 + l * 3 + c] = float(ch[size_t(c)].se[g][size_t(l)][size_t(cell)]);
                }
            p[30] = float(projected[g][size_t(cell)]);
        }
        specs.push_back(spec);
        pixels.push_back(std::move(px));
    }
    // Multi-part EXR: every part shares one display window.
    int fullW = 1, fullH = 1;
    for (const OIIO::ImageSpec& sp : specs) {
        fullW = std::max(fullW, sp.width);
        fullH = std::max(fullH, sp.height);
    }
    for (OIIO::ImageSpec& sp : specs) {
        sp.full_x = sp.full_y = 0;
        sp.full_width = fullW;
        sp.full_height = fullH;
    }
    const std::string tmp = path + ".tmp" + std::to_string(getpid());
    auto out = OIIO::ImageOutput::create("openexr");
    if (!out) throw InputError(path + ": cannot create an EXR writer");
    bool ok = out->open(tmp, int(specs.size()), specs.data());
    for (size_t g = 0; ok && g < specs.size(); ++g) {
        if (g > 0) ok = out->open(tmp, specs[g], OIIO::ImageOutput::AppendSubimage);
        ok = ok && out->write_image(OIIO::TypeDesc::FLOAT, pixels[g].data());
    }
    ok = out->close() && ok;
    std::error_code ec;
    if (!ok) {
        const std::string err = out->geterror();
        fs::remove(tmp, ec);
        throw InputError(path + ": cannot write (" + err + ")");
    }
    fs::rename(tmp, path, ec);
    if (ec) throw InputError(path + ": cannot write (" + ec.message() + ")");
}

int simulate_command(const Params& params, const std::vector<double>& thetas, double phi,
                     std::uint64_t rays, std::uint64_t seed, int threads, const std::string& prefix,
                     bool wayUpThroughPrisms) {
    check_prefix(prefix);
    const Params p = sanitize(params);
    // One simulation per distinct substrate albedo among the colour channels (the rest of the
    // geometry is grey); retro_color, specular and weight multiply the lobes.
    int runOf[3] = {0, 1, 2};
    for (int c = 1; c < 3; ++c)
        for (int e = 0; e < c; ++e)
            if (p.diffuse_color[size_t(c)] == p.diffuse_color[size_t(e)]) {
                runOf[c] = runOf[e];
                break;
            }
    json doc;
    doc["material"] = params_to_json(p);
    doc["simulator"] = {
        {"rays_per_direction", rays},
        {"seed", seed},
        {"way_up", wayUpThroughPrisms ? "through_prisms" : "direct"},
        {"description",
         "Monte Carlo through the explicit microgeometry (sim/microgeometry.h): Smith random walk "
         "on the rough top surface, exact cube-corner tracing, Lambertian substrate; f per lobe "
         "as cosine-weighted cell averages [1/sr] with binomial standard errors"}};
    doc["incidences"] = json::array();
    double totalRays = 0, totalSeconds = 0;
    int usedThreads = 1;
    for (double thetaI : thetas) {
        const dvec3 wi = direction_deg(thetaI, phi);
        sim::Sheet base = sim::sheet_from_params(p, 0);
        base.upward_through_prisms = wayUpThroughPrisms;
        const std::vector<sim::Grid> grids = sim::standard_grids(base, wi);
        f64::rp_material m = prepare_material(p);
        m.retro_anisotropic = 1;
        f64::rp_incident s;
        f64::rp_incident_setup(m, wi, s);
        const std::vector<sim::Feature> features = {{wi, s.alphaPerp},
                                                    {dvec3(-wi.x, -wi.y, wi.z), base.alpha}};
        std::vector<std::vector<double>> projected;
        for (const sim::Grid& g : grids)
            projected.push_back(
                sim::integrate_cells(g, 0, nullptr, features, 4, 64, threads).projected);
        std::array<sim::Run, 3> runs;
        for (int c = 0; c < 3; ++c) {
            if (runOf[c] != c) continue;
            sim::Sheet sh = sim::sheet_from_params(p, c);
            sh.upward_through_prisms = wayUpThroughPrisms;
            ProgressBar bar("simulate theta_i " + fmt("%g", thetaI) +
                            (runOf[1] == 0 && runOf[2] == 0 ? "" : fmt(" channel %.0f", c)));
            sim::RunOptions opt;
            opt.rays = rays;
            opt.seed = seed;
            opt.threads = threads;
            opt.progress = [&bar](std::uint64_t d, std::uint64_t t) { bar(d, t); };
            runs[size_t(c)] = sim::simulate(sh, wi, grids, opt);
            totalRays += double(rays);
            totalSeconds += runs[size_t(c)].seconds;
            usedThreads = runs[size_t(c)].threads;
        }
        // Per channel: factors of the lobes (k_s, c_r, 1) times the weight.
        std::array<ChannelData, 3> ch;
        for (int c = 0; c < 3; ++c) {
            const sim::Tally& t = runs[size_t(runOf[c])].tally;
            const double n = double(t.rays);
            const double factor[4] = {p.weight * p.specular, p.weight * p.specular,
                                      p.weight * p.retro_color[size_t(c)], p.weight};
            ch[size_t(c)].f.resize(grids.size());
            ch[size_t(c)].se.resize(grids.size());
            for (size_t g = 0; g < grids.size(); ++g) {
                for (auto& v : ch[size_t(c)].f[g])
                    v.assign(size_t(grids[g].cells()), 0.0);
                for (auto& v : ch[size_t(c)].se[g])
                    v.assign(size_t(grids[g].cells()), 0.0);
                for (int cell = 0; cell < grids[g].cells(); ++cell) {
                    const double proj = projected[g][size_t(cell)];
                    if (!(proj > 0)) continue;
                    double pr[4], mean = 0, second = 0;
                    for (int k = 0; k < 4; ++k) {
                        pr[k] = double(t.counts[g][size_t(cell) * sim::kChannels + size_t(k)]) / n;
                        const sim::Estimate e = sim::fraction(
                            t.counts[g][size_t(cell) * sim::kChannels + size_t(k)], t.rays);
                        ch[size_t(c)].f[g][size_t(k)][size_t(cell)] = factor[k] * e.value / proj;
                        ch[size_t(c)].se[g][size_t(k)][size_t(cell)] = factor[k] * e.se / proj;
                    }
                    // The total: surface + retro + diffuse, with the multinomial variance of a
                    // weighted sum of exclusive categories.
                    for (int k : {sim::kSurface, sim::kRetro, sim::kDiffuse}) {
                        mean += factor[k] * pr[k];
                        second += factor[k] * factor[k] * pr[k];
                    }
                    ch[size_t(c)].f[g][4][size_t(cell)] = mean / proj;
                    ch[size_t(c)].se[g][4][size_t(cell)] =
                        std::sqrt(std::max(0.0, second - mean * mean) / n) / proj;
                }
            }
        }
        const sim::Run& r0 = runs[0];
        json inc;
        inc["theta_i_deg"] = thetaI;
        inc["phi_i_deg"] = phi;
        inc["wi"] = {r7(wi.x), r7(wi.y), r7(wi.z)};
        inc["rays"] = rays;
        inc["threads"] = r0.threads;
        inc["seconds"] = r7(r0.seconds);
        inc["rays_per_second"] = r7(r0.rays_per_second());
        json fates = json::object();
        for (int fate = 0; fate < sim::kFates; ++fate) {
            json perChannel = json::array();
            for (int c = 0; c < 3; ++c)
                perChannel.push_back(
                    r7(double(runs[size_t(runOf[c])].tally.fates[size_t(fate)]) / double(rays)));
            fates[sim::fate_name(fate)] = perChannel;
        }
        inc["fates_fraction_rgb"] = fates;
        inc["retro_primary_fraction"] = r7(double(r0.tally.retro_primary) / double(rays));
        inc["surface_single_fraction"] = r7(double(r0.tally.surface_single) / double(rays));
        json jg = json::array();
        for (size_t g = 0; g < grids.size(); ++g) {
            const sim::Grid& grid = grids[g];
            const char* kinds[4] = {"gnomonic", "disk", "strip", "cone"};
            json o;
            o["name"] = grid.name;
            o["kind"] = kinds[grid.kind];
            o["c"] = {r7(grid.c.x), r7(grid.c.y), r7(grid.c.z)};
            o["e1"] = {r7(grid.e1.x), r7(grid.e1.y), r7(grid.e1.z)};
            o["e2"] = {r7(grid.e2.x), r7(grid.e2.y), r7(grid.e2.z)};
            o["x0_x1_y0_y1"] = {r7(grid.x0), r7(grid.x1), r7(grid.y0), r7(grid.y1)};
            o["nx"] = grid.nx;
            o["ny"] = grid.ny;
            json centres = json::array(), proj = json::array();
            for (int cell = 0; cell < grid.cells(); ++cell) {
                const dvec3 w = grid.cell_centre(cell);
                centres.push_back({r7(w.x), r7(w.y), r7(w.z)});
                proj.push_back(r7(projected[g][size_t(cell)]));
            }
            o["cell_centre"] = centres;
            o["projected_solid_angle"] = proj;
            for (int l = 0; l < 5; ++l) {
                json fv = json::array(), sv = json::array();
                for (int cell = 0; cell < grid.cells(); ++cell) {
                    json a = json::array(), b = json::array();
                    for (int c = 0; c < 3; ++c) {
                        a.push_back(r7(ch[size_t(c)].f[g][size_t(l)][size_t(cell)]));
                        b.push_back(r7(ch[size_t(c)].se[g][size_t(l)][size_t(cell)]));
                    }
                    fv.push_back(a);
                    sv.push_back(b);
                }
                o[std::string(kOutLobes[l])] = {{"f", fv}, {"se", sv}};
            }
            jg.push_back(o);
        }
        inc["grids"] = jg;
        const std::string exrPath = prefix + "_theta" + fmt("%g", thetaI) + ".exr";
        json meta = {{"theta_i_deg", thetaI}, {"phi_i_deg", phi}, {"rays", rays}, {"seed", seed}};
        write_exr(exrPath, grids, projected, ch, meta);
        inc["exr"] = exrPath;
        doc["incidences"].push_back(inc);
        const sim::Tally& t = r0.tally;
        std::printf(
            "theta_i %5.1f: surface %.5f  retro %.5f  diffuse %.5f  absorbed %.5f  "
            "trapped %llu  (channel 0, %llu rays, %.3g rays/s on %d threads) -> %s\n",
            thetaI, double(t.fates[sim::kFateSurface]) / double(rays),
            double(t.fates[sim::kFateRetro]) / double(rays),
            double(t.fates[sim::kFateDiffuse]) / double(rays),
            double(t.fates[sim::kFateAbsorbedSubstrate] + t.fates[sim::kFateAbsorbedFaces]) /
                double(rays),
            (unsigned long long)t.fates[sim::kFateTrapped], (unsigned long long)rays,
            r0.rays_per_second(), r0.threads, exrPath.c_str());
    }
    const std::string jsonPath = prefix + ".json";
    const std::string tmp = jsonPath + ".tmp" + std::to_string(getpid());
    {
        std::ofstream f(tmp);
        f << doc.dump() << "\n";
        if (!f) throw InputError(jsonPath + ": cannot write");
    }
    std::error_code ec;
    fs::rename(tmp, jsonPath, ec);
    if (ec) throw InputError(jsonPath + ": cannot write (" + ec.message() + ")");
    std::printf("wrote %s; %.4g rays/s on %d threads overall\n", jsonPath.c_str(),
                totalSeconds > 0 ? totalRays / totalSeconds : 0.0, usedThreads);
    return 0;
}

// =============================================================================================
// The accuracy study: every analytic variant against the simulator (`simulate --study`).

struct Variant {
    const char* name;
    const char* key;
    int aniso;
    int recip;
};
const Variant kVariants[4] = {{"isotropic (paper)", "iso", 0, 0},
                              {"anisotropic", "aniso", 1, 0},
                              {"isotropic + reciprocal", "iso+rec", 0, 1},
                              {"anisotropic + reciprocal", "aniso+rec", 1, 1}};

const std::vector<double> kStudyThetas = {0, 20, 40, 60, 75, 85};
const std::vector<double> kStudyAlphas = {0.005, 0.02, 0.1, 0.3};
const std::vector<double> kStudyEtas = {1.49, 1.586};
const std::vector<int> kStudyPrisms = {f64::RP_PRISM_TIR, f64::RP_PRISM_METALLIZED};
constexpr double kStudyKd = 0.9;
constexpr double kRecipConeDeg = 4.0;   // reciprocity: cones of incidence and exit
constexpr double kDiffuseConeDeg = 5.0; // diffuse-level cones
constexpr double kResolvedSe = 0.05;    // a metric counts when the simulation knows it to 5%
constexpr double kDiffuseAlpha = 0.1;   // roughness of the diffuse-model comparison
constexpr int kGridRetro = 0, kGridMirror = 1, kGridHemi = 2, kGridInPlane = 3, kGridNormal = 5,
              kGridD60 = 6;

struct Config {
    double theta, alpha, eta;
    int prism;
};

const char* prism_name(int prism) {
    return prism == f64::RP_PRISM_TIR          ? "tir"
           : prism == f64::RP_PRISM_METALLIZED ? "metallized"
                                               : "ideal";
}

std::string config_label(const Config& c) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%g deg, alpha %g, eta %g, %s", c.theta, c.alpha, c.eta,
                  prism_name(c.prism));
    return buf;
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

struct ProbeDir {
    double theta, phi;
};
std::vector<ProbeDir> probe_dirs() {
    std::vector<ProbeDir> out;
    for (double t : kStudyThetas)
        for (double ph : {0.0, 180.0})
            if (t > 0 || ph == 0) out.push_back({t, ph});
    return out;
}

struct VariantResult {
    double alphaPar = 0, alphaPerp = 0; // the variant's lobe widths at wi
    sim::LobeFit fit;                   // fitted on the simulation's cells, with its weights
    double peak = 0, energy = 0, surface = 0, diffuseNormal = 0, diffuse60 = 0, diffuseAlbedo = 0;
    double l1 = 0, l1Retro = 0;
    std::vector<double> row, col;             // f_r on the retro grid's centre row / column
    std::array<std::vector<double>, 4> strip; // in-plane f: surface, retro, diffuse, total
};

struct SimResult {
    std::uint64_t rays = 0;
    double seconds = 0;
    int threads = 1;
    sim::LobeFit fit;
    sim::Estimate peak, energy, energyPrimary, energyMultiple, diffuseNormal, diffuse60,
        diffuseAlbedo, surface, surfaceSingle, absorbed;
    std::uint64_t trapped = 0;
    double l1Noise = 0, l1RetroNoise = 0;
    std::vector<double> rowX, colX, stripX;
    std::vector<sim::Estimate> row, col;
    std::array<std::vector<sim::Estimate>, 4> strip;

    double hx = 0, hy = 0; // retro grid half-widths (slopes)
};

struct ConfigResult {
    Config c{};
    SimResult sim;
    std::array<VariantResult, 4> v;
};

// Total f of a cell: surface + retro + diffuse, binomial (the categories are exclusive).
sim::Estimate total_estimate(const sim::Tally& t, int grid, int cell, double projected) {
    const std::uint64_t* c = &t.counts[size_t(grid)][size_t(cell) * sim::kChannels];
    sim::Estimate e = sim::fraction(c[sim::kSurface] + c[sim::kRetro] + c[sim::kDiffuse], t.rays);
    if (!(projected > 0)) return sim::Estimate();
    e.value /= projected;
    e.se /= projected;
    return e;
}

ConfigResult run_config(const Config& cfg, std::uint64_t rays, std::uint64_t seed,
                        bool throughPrisms, bool analytic, int threads, const std::string& label) {
    ConfigResult out;
    out.c = cfg;
    const dvec3 wi = direction_deg(cfg.theta, 0);
    const dvec3 wr(-wi.x, -wi.y, wi.z);
    sim::Sheet sheet = sim::sheet_from_params(config_params(cfg, 0), 0);
    sheet.upward_through_prisms = throughPrisms;
    std::vector<sim::Grid> grids = sim::standard_grids(sheet, wi);
    grids.push_back(sim::cone_grid("normal", dvec3(0, 0, 1), kDiffuseConeDeg * kDeg));
    grids.push_back(sim::cone_grid("d60", direction_deg(60, 90), kDiffuseConeDeg * kDeg));

    ProgressBar bar(label);
    sim::RunOptions opt;
    opt.rays = rays;
    opt.seed = seed;
    opt.threads = threads;
    opt.progress = [&bar](std::uint64_t d, std::uint64_t n) { bar(d, n); };
    const sim::Run run = sim::simulate(sheet, wi, grids, opt);
    const sim::Tally& t = run.tally;
    const double n = double(t.rays);
    SimResult& s = out.sim;
    s.rays = t.rays;
    s.seconds = run.seconds;
    s.threads = run.threads;
    s.hx = grids[kGridRetro].x1;
    s.hy = grids[kGridRetro].y1;

    // The cells' measures, with the quadrature the analytic integrals use (the same features).
    f64::rp_material ma = prepare_material(sanitize(config_params(cfg, 1)));
    f64::rp_incident sa;
    f64::rp_incident_setup(ma, wi, sa);
    const std::vector<sim::Feature> features = {{wi, sa.alphaPerp}, {wr, sheet.alpha}};
    auto minS = [](int g) { return g == kGridHemi ? 3 : g >= kGridNormal ? 12 : 4; };
    std::vector<sim::CellIntegrals> meas(grids.size());
    for (size_t g = 0; g < grids.size(); ++g)
        meas[g] = sim::integrate_cells(grids[g], 0, nullptr, features, minS(int(g)), 64, threads);

    const sim::Grid& rg = grids[kGridRetro];
    // The retro peak: the 3 x 3 cells about wi (the grid's centre cell is centred on wi).
    std::vector<int> centreCells;
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
            centreCells.push_back((rg.ny / 2 + dj) * rg.nx + rg.nx / 2 + di);
    {
        std::uint64_t cnt = 0;
        double proj = 0;
        for (int c : centreCells) {
            cnt += t.counts[kGridRetro][size_t(c) * sim::kChannels + sim::kRetro];
            proj += meas[kGridRetro].projected[size_t(c)];
        }
        s.peak = sim::fraction(cnt, t.rays);
        s.peak.value /= proj;
        s.peak.se /= proj;
    }
    s.energy = sim::fraction(t.fates[sim::kFateRetro], t.rays);
    s.energyPrimary = sim::fraction(t.retro_primary, t.rays);
    s.energyMultiple = sim::fraction(t.retro_multiple, t.rays);
    s.diffuseNormal =
        sim::cell_brdf(t, kGridNormal, 0, sim::kDiffuse, meas[kGridNormal].projected[0]);
    s.diffuse60 = sim::cell_brdf(t, kGridD60, 0, sim::kDiffuse, meas[kGridD60].projected[0]);
    s.diffuseAlbedo = sim::fraction(t.fates[sim::kFateDiffuse], t.rays);
    s.surface = sim::fraction(t.fates[sim::kFateSurface], t.rays);
    s.surfaceSingle = sim::fraction(t.surface_single, t.rays);
    s.absorbed = sim::fraction(
        t.fates[sim::kFateAbsorbedSubstrate] + t.fates[sim::kFateAbsorbedFaces], t.rays);
    s.trapped = t.fates[sim::kFateTrapped];

    // The fit's cells: enough counts, within e^-3 of the peak, mostly above the horizon.
    const int cells = rg.cells();
    const double fullArea = (rg.x1 - rg.x0) * (rg.y1 - rg.y0) / cells;
    std::vector<double> density(size_t(cells), 0.0), weight(size_t(cells), 0.0);
    std::vector<char> use(size_t(cells), 0);
    double peakCount = 0;
    for (int c = 0; c < cells; ++c)
        peakCount = std::max(
            peakCount, double(t.counts[kGridRetro][size_t(c) * sim::kChannels + sim::kRetro]));
    for (int c = 0; c < cells; ++c) {
        const double cnt = double(t.counts[kGridRetro][size_t(c) * sim::kChannels + sim::kRetro]);
        const double area = meas[kGridRetro].param_area[size_t(c)];
        density[size_t(c)] = area > 0 ? cnt / area : 0;
        weight[size_t(c)] = cnt;
        use[size_t(c)] = cnt >= 16 && cnt >= std::exp(-3.0) * peakCount && area >= 0.5 * fullArea;
    }
    s.fit = sim::fit_lobe(rg, density, weight, use);

    // Noise floors of the L1 errors: the mean absolute deviation of each cell's estimate.
    auto noise = [&](int g, bool retroOnly) {
        double sum = 0, mass = 0;
        for (int c = 0; c < grids[size_t(g)].cells(); ++c) {
            const std::uint64_t* k = &t.counts[size_t(g)][size_t(c) * sim::kChannels];
            const double p =
                double(retroOnly ? k[sim::kRetro]
                                 : k[sim::kSurface] + k[sim::kRetro] + k[sim::kDiffuse]) /
                n;
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
        s.row.push_back(
            sim::cell_brdf(t, kGridRetro, c, sim::kRetro, meas[kGridRetro].projected[size_t(c)]));
    }
    for (int j = 0; j < rg.ny; ++j) {
        const int c = j * rg.nx + midCol;
        s.colX.push_back(std::atan(rg.y0 + (j + 0.5) * (rg.y1 - rg.y0) / rg.ny) / kDeg);
        s.col.push_back(
            sim::cell_brdf(t, kGridRetro, c, sim::kRetro, meas[kGridRetro].projected[size_t(c)]));
    }
    const sim::Grid& sg = grids[kGridInPlane];
    for (int i = 0; i < sg.nx; ++i) {
        const double proj = meas[kGridInPlane].projected[size_t(i)];
        s.stripX.push_back((sg.x0 + (i + 0.5) * (sg.x1 - sg.x0) / sg.nx) / kDeg);
        s.strip[0].push_back(sim::cell_brdf(t, kGridInPlane, i, sim::kSurface, proj));
        s.strip[1].push_back(sim::cell_brdf(t, kGridInPlane, i, sim::kRetro, proj));
        s.strip[2].push_back(sim::cell_brdf(t, kGridInPlane, i, sim::kDiffuse, proj));
        s.strip[3].push_back(total_estimate(t, kGridInPlane, i, proj));
    }

    if (!analytic) return out;

    for (int v = 0; v < 4; ++v) {
        VariantResult& r = out.v[size_t(v)];
        const Params p = config_params(cfg, v);
        f64::rp_material m = prepare_material(sanitize(p));
        f64::rp_incident si;
        f64::rp_incident_setup(m, wi, si);
        r.alphaPar = si.alphaPar;
        r.alphaPerp = si.alphaPerp;
        const sim::CellFunction f = sim::model_function(p, wi);
        auto integ = [&](int g) {
            return sim::integrate_cells(grids[size_t(g)], 3, f, features, minS(g), 64, threads);
        };
        const sim::CellIntegrals ciR = integ(kGridRetro), ciH = integ(kGridHemi),
                                 ciS = integ(kGridInPlane), ciN = integ(kGridNormal),
                                 ciD = integ(kGridD60);
        {
            double e = 0, proj = 0;
            for (int c : centreCells) {
                e += ciR.values[size_t(c) * 3 + 1];
                proj += ciR.projected[size_t(c)];
            }
            r.peak = e / proj;
        }
        std::vector<double> da(size_t(cells), 0.0);
        for (int c = 0; c < cells; ++c) {
            const double area = ciR.param_area[size_t(c)];
            da[size_t(c)] = area > 0 ? ciR.values[size_t(c) * 3 + 1] * n / area : 0;
        }
        r.fit = sim::fit_lobe(rg, da, weight, use);
        double l1 = 0, mass = 0;
        for (int c = 0; c < grids[kGridHemi].cells(); ++c) {
            const double* a = &ciH.values[size_t(c) * 3];
            r.surface += a[0];
            r.energy += a[1];
            r.diffuseAlbedo += a[2];
            const std::uint64_t* k = &t.counts[kGridHemi][size_t(c) * sim::kChannels];
            const double es = double(k[sim::kSurface] + k[sim::kRetro] + k[sim::kDiffuse]) / n;
            l1 += std::abs(a[0] + a[1] + a[2] - es);
            mass += es;
        }
        r.l1 = mass > 0 ? l1 / mass : 0;
        double l1r = 0, massR = 0;
        for (int c = 0; c < cells; ++c) {
            const double es =
                double(t.counts[kGridRetro][size_t(c) * sim::kChannels + sim::kRetro]) / n;
            l1r += std::abs(ciR.values[size_t(c) * 3 + 1] - es);
            massR += es;
        }
        r.l1Retro = massR > 0 ? l1r / massR : 0;
        r.diffuseNormal = ciN.values[2] / ciN.projected[0];
        r.diffuse60 = ciD.values[2] / ciD.projected[0];
        for (int i = 0; i < rg.nx; ++i) {
            const int c = midRow * rg.nx + i;
            r.row.push_back(ciR.values[size_t(c) * 3 + 1] / ciR.projected[size_t(c)]);
        }
        for (int j = 0; j < rg.ny; ++j) {
            const int c = j * rg.nx + midCol;
            r.col.push_back(ciR.values[size_t(c) * 3 + 1] / ciR.projected[size_t(c)]);
        }
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
    }
    return out;
}

// ---- Plots
// ---------------------------------------------------------------------------------------

using Rgb = std::array<float, 3>;
const Rgb kBg = {0.055f, 0.06f, 0.075f};
const Rgb kPlotBg = {0.09f, 0.095f, 0.115f};
const Rgb kGridCol = {0.22f, 0.23f, 0.27f};
const Rgb kAxisCol = {0.6f, 0.62f, 0.66f};
const Rgb kTextCol = {0.88f, 0.89f, 0.92f};
const Rgb kDimCol = {0.62f, 0.64f, 0.68f};
const Rgb kSimCol = {1.0f, 1.0f, 1.0f};
const Rgb kVariantCol[4] = {
    {1.0f, 0.45f, 0.18f}, {0.30f, 0.72f, 1.0f}, {0.95f, 0.85f, 0.25f}, {0.85f, 0.4f, 0.95f}};
const Rgb kDiffuseCol = {0.40f, 0.88f, 0.35f};
const Rgb kDiffuseRecCol = {0.15f, 0.65f, 0.65f};
const char* kFont = "DejaVuSans";

struct Text {
    bool ok = true;
    void draw(OIIO::ImageBuf& img, int x, int y, const std::string& s, int size, const Rgb& color,
              OIIO::ImageBufAlgo::TextAlignX ax = OIIO::ImageBufAlgo::TextAlignX::Left,
              OIIO::ImageBufAlgo::TextAlignY ay = OIIO::ImageBufAlgo::TextAlignY::Baseline) {
        if (!ok) return;
        if (!OIIO::ImageBufAlgo::render_text(img, x, y, s, size, kFont, color, ax, ay)) {
            ok = false;
            std::fprintf(stderr,
                         "retroprism simulate: note: no font for labels; plots without text\n");
        }
    }
};

struct Series {
    std::vector<double> x, y, err; // err: points with +-2 se bars; empty: a line
    Rgb color;
    bool dashed = false;
    int width = 2;
};
struct Panel {
    std::string title;
    std::vector<Series> series;
    bool logY = false;
    double x0 = -1, x1 = 1;
    std::vector<std::pair<double, Rgb>> vlines;
};
struct Figure {
    std::string title, xLabel, yLabel;
    std::vector<std::string> rowHeads, colHeads;
    int rows = 1, cols = 1;
    std::vector<Panel> panels; // row-major
    std::vector<std::pair<std::string, Series>> legend;
    std::vector<std::string> caption;
};

// 1, 2 or 5 times a power of ten, about (range / target).
double nice_step(double range, int target) {
    const double raw = range / target;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

// A float RGB canvas with clipped lines and boxes (the plots' geometry; OpenImageIO draws the
// text and writes the file).
struct Canvas {
    int w, h;
    std::vector<float> px;
    Canvas(int width, int height, const Rgb& bg)
        : w(width), h(height), px(size_t(width) * size_t(height) * 3) {
        for (size_t i = 0; i < px.size(); ++i)
            px[i] = bg[i % 3];
    }
    struct Clip {
        int x0, y0, x1, y1; // inclusive
    };
    Clip all() const { return {0, 0, w - 1, h - 1}; }
    void set(int x, int y, const Rgb& c, const Clip& cl) {
        if (x < std::max(0, cl.x0) || y < std::max(0, cl.y0) || x > std::min(w - 1, cl.x1) ||
            y > std::min(h - 1, cl.y1))
            return;
        float* p = &px[(size_t(y) * size_t(w) + size_t(x)) * 3];
        p[0] = c[0];
        p[1] = c[1];
        p[2] = c[2];
    }
    void fill(int x0, int y0, int x1, int y1, const Rgb& c, const Clip& cl) {
        for (int y = std::max(y0, 0); y <= std::min(y1, h - 1); ++y)
            for (int x = std::max(x0, 0); x <= std::min(x1, w - 1); ++x)
                set(x, y, c, cl);
    }
    // Bresenham, endpoints limited to a box around the canvas (off-canvas parts are clipped).
    void line(int x1, int y1, int x2, int y2, const Rgb& c, int width, const Clip& cl) {
        const int lim = 4 * (w + h);
        x1 = std::clamp(x1, -lim, lim);
        x2 = std::clamp(x2, -lim, lim);
        y1 = std::clamp(y1, -lim, lim);
        y2 = std::clamp(y2, -lim, lim);
        const int dx = std::abs(x2 - x1), dy = -std::abs(y2 - y1);
        const int sx = x1 < x2 ? 1 : -1, sy = y1 < y2 ? 1 : -1;
        int err = dx + dy, x = x1, y = y1;
        const int lo = -(width - 1) / 2, hi = width / 2;
        for (int guard = 0; guard < 4 * lim; ++guard) {
            for (int ox = lo; ox <= hi; ++ox)
                for (int oy = lo; oy <= hi; ++oy)
                    set(x + ox, y + oy, c, cl);
            if (x == x2 && y == y2) break;
            const int e2 = 2 * err;
            if (e2 >= dy) {
                err += dy;
                x += sx;
            }
            if (e2 <= dx) {
                err += dx;
                y += sy;
            }
        }
    }
    void rect(int x0, int y0, int x1, int y1, const Rgb& c) {
        line(x0, y0, x1, y0, c, 1, all());
        line(x1, y0, x1, y1, c, 1, all());
        line(x1, y1, x0, y1, c, 1, all());
        line(x0, y1, x0, y0, c, 1, all());
    }
};

// Text to draw once the geometry is done.
struct Label {
    int x, y;
    std::string s;
    int size;
    Rgb color;
    OIIO::ImageBufAlgo::TextAlignX ax;
    OIIO::ImageBufAlgo::TextAlignY ay;
};

// A pixel coordinate from a value, never beyond the int range (NaN: far outside).
int pixel(double v) {
    if (!std::isfinite(v)) return -1000000;
    return int(std::lround(std::clamp(v, -1e6, 1e6)));
}

OIIO::ImageBuf render_figure(const Figure& fig, Text& text) {
    namespace IBA = OIIO::ImageBufAlgo;
    using AX = IBA::TextAlignX;
    using AY = IBA::TextAlignY;
    const int pw = 300, ph = 190, padL = 58, padR = 14, padT = 34, padB = 40;
    const int left = 110, top = 96, cellW = padL + pw + padR, cellH = padT + ph + padB;
    int legendW = 0;
    for (const auto& e : fig.legend)
        legendW += 60 + 8 * int(e.first.size());
    const int W = std::max(left + fig.cols * cellW + 20, left + legendW + 20);
    const int H = top + fig.rows * cellH + 60 + 22 * int(fig.caption.size());
    Canvas cv(W, H, kBg);
    std::vector<Label> labels;
    auto label = [&](int x, int y, const std::string& s, int size, const Rgb& c, AX ax = AX::Left,
                     AY ay = AY::Baseline) {
        labels.push_back({x, y, s, size, c, ax, ay});
    };
    label(20, 34, fig.title, 22, kTextCol);
    for (int c = 0; c < fig.cols && c < int(fig.colHeads.size()); ++c)
        label(left + c * cellW + padL + pw / 2, top - 18, fig.colHeads[size_t(c)], 17, kTextCol,
              AX::Center);
    for (int r = 0; r < fig.rows && r < int(fig.rowHeads.size()); ++r)
        label(14, top + r * cellH + padT + ph / 2, fig.rowHeads[size_t(r)], 16, kTextCol, AX::Left,
              AY::Center);
    for (int r = 0; r < fig.rows; ++r) {
        for (int c = 0; c < fig.cols; ++c) {
            const Panel& pan = fig.panels[size_t(r * fig.cols + c)];
            const int x0 = left + c * cellW + padL, y0 = top + r * cellH + padT;
            const int x1 = x0 + pw, y1 = y0 + ph;
            const Canvas::Clip clip{x0, y0, x1, y1};
            cv.fill(x0, y0, x1, y1, kPlotBg, cv.all());
            double vmax = 0;
            for (const Series& s : pan.series)
                for (size_t i = 0; i < s.y.size(); ++i) {
                    if (s.x[i] < pan.x0 || s.x[i] > pan.x1 || !std::isfinite(s.y[i])) continue;
                    const double hiV = s.y[i] + (s.err.empty() ? 0 : 2 * s.err[i]);
                    if (std::isfinite(hiV)) vmax = std::max(vmax, hiV);
                }
            double ylo, yhi;
            if (pan.logY) {
                yhi = vmax > 0 ? std::ceil(std::log10(vmax) + 0.02) : 0;
                ylo = yhi - 5;
            } else {
                ylo = 0;
                yhi = vmax > 0 ? vmax * 1.08 : 1;
            }
            auto X = [&](double x) { return pixel(x0 + (x - pan.x0) / (pan.x1 - pan.x0) * pw); };
            auto Y = [&](double v) {
                double u = pan.logY ? (v > 0 ? std::log10(v) : ylo - 1) : v;
                u = std::clamp(u, ylo - 0.02 * (yhi - ylo), yhi);
                return pixel(y1 - (u - ylo) / (yhi - ylo) * ph);
            };
            if (pan.logY) {
                for (int d = int(ylo); d <= int(yhi); ++d) {
                    const int yy = pixel(y1 - (d - ylo) / (yhi - ylo) * ph);
                    cv.line(x0, yy, x1, yy, kGridCol, 1, clip);
                    label(x0 - 6, yy, fmt("1e%+.0f", d), 12, kDimCol, AX::Right, AY::Center);
                }
            } else {
                const double st = nice_step(yhi - ylo, 4);
                for (int i = 0; i <= 20 && i * st <= yhi; ++i) {
                    cv.line(x0, Y(i * st), x1, Y(i * st), kGridCol, 1, clip);
                    label(x0 - 6, Y(i * st), fmt(st < 0.01 ? "%.1e" : "%g", i * st), 12, kDimCol,
                          AX::Right, AY::Center);
                }
            }
            const double sx = nice_step(pan.x1 - pan.x0, 4);
            const double first = std::ceil(pan.x0 / sx) * sx;
            for (int i = 0; i <= 20 && first + i * sx <= pan.x1 + 1e-9; ++i) {
                const double v = first + i * sx;
                cv.line(X(v), y0, X(v), y1, kGridCol, 1, clip);
                label(X(v), y1 + 16,
                      fmt(sx < 0.1 ? "%.2f"
                          : sx < 1 ? "%.1f"
                                   : "%.0f",
                          v),
                      12, kDimCol, AX::Center);
            }
            for (const auto& vl : pan.vlines)
                for (int yy = y0; yy < y1; yy += 8)
                    cv.line(X(vl.first), yy, X(vl.first), std::min(yy + 4, y1), vl.second, 1, clip);
            for (const Series& s : pan.series) {
                if (s.err.empty()) {
                    int px = 0, py = 0;
                    bool have = false;
                    for (size_t i = 0; i < s.x.size(); ++i) {
                        if (!std::isfinite(s.y[i])) {
                            have = false;
                            continue;
                        }
                        const int xx = X(s.x[i]), yy = Y(s.y[i]);
                        if (have && (!s.dashed || i % 2 == 0))
                            cv.line(px, py, xx, yy, s.color, s.width, clip);
                        px = xx;
                        py = yy;
                        have = true;
                    }
                } else {
                    for (size_t i = 0; i < s.x.size(); ++i) {
                        if (!std::isfinite(s.y[i]) || (pan.logY && !(s.y[i] > 0))) continue;
                        const int xx = X(s.x[i]), yc = Y(s.y[i]);
                        const double e = std::isfinite(s.err[i]) ? s.err[i] : 0.0;
                        const int ya = Y(std::max(s.y[i] - 2 * e, pan.logY ? s.y[i] * 0.1 : 0.0));
                        const int yb = Y(s.y[i] + 2 * e);
                        cv.line(xx, ya, xx, yb, s.color, 1, clip);
                        cv.fill(xx - 1, yc - 1, xx + 1, yc + 1, s.color, clip);
                    }
                }
            }
            cv.rect(x0, y0, x1, y1, kAxisCol);
            label(x0 + 6, y0 - 8, pan.title, 13, kDimCol);
        }
    }
    const int by = top + fig.rows * cellH + 8;
    label(left + fig.cols * cellW / 2, by, fig.xLabel, 15, kTextCol, AX::Center);
    label(20, 62, fig.yLabel, 15, kDimCol);
    int lx = left;
    for (const auto& e : fig.legend) {
        if (e.second.err.empty())
            cv.line(lx, by + 26, lx + 34, by + 26, e.second.color, e.second.width, cv.all());
        else
            cv.fill(lx + 14, by + 23, lx + 20, by + 29, e.second.color, cv.all());
        label(lx + 42, by + 26, e.first, 14, kTextCol, AX::Left, AY::Center);
        lx += 60 + 8 * int(e.first.size());
    }
    for (size_t i = 0; i < fig.caption.size(); ++i)
        label(20, by + 56 + 22 * int(i), fig.caption[i], 13, kDimCol);
    OIIO::ImageBuf img(OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT));
    img.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, cv.px.data());
    for (const Label& l : labels)
        if (l.x >= 0 && l.x < W && l.y >= 0 && l.y < H)
            text.draw(img, l.x, l.y, l.s, l.size, l.color, l.ax, l.ay);
    return img;
}

void write_png(const OIIO::ImageBuf& img, const fs::path& path) {
    const fs::path tmp =
        path.parent_path() / ("." + path.filename().string() + ".tmp" + std::to_string(getpid()));
    if (!img.write(tmp.string(), OIIO::TypeDesc::UINT8, "png"))
        throw InputError(path.string() + ": cannot write (" + img.geterror() + ")");
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw InputError(path.string() + ": cannot write (" + ec.message() + ")");
}

// ---- Summaries
// --------------------------------------------------------------------------------------

std::string pct(double v) {
    if (!std::isfinite(v)) return "n/a";
    return fmt("%+.1f%%", 100 * v);
}

// The worst (largest |value|) of a metric over a set of configurations, with where it is.
struct Worst {
    double value = 0;
    bool any = false;
    std::string where;
    int counted = 0, unresolved = 0;
    void add(double v, bool resolved, const std::string& w) {
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
    std::string str(bool withWhere = false) const {
        if (!any) return "n/a";
        return pct(value) + (withWhere ? " (" + where + ")" : "");
    }
};

double rel_se(const sim::Estimate& e) {
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

struct StudyOptions {
    std::uint64_t rays = 4000000;
    std::uint64_t diffuseRays = 1000000;
    std::uint64_t recipRays = 400000;
    std::uint64_t seed = 2018;
    int threads = 0;
    fs::path doc = "docs/accuracy.md";
    bool quick = false;
    std::string save, load; // results file to write / to read instead of simulating
};

std::string key_of(double alpha, double eta, int prism);

// One pair of cones A, B of the reciprocity runs: Q(A, B) = integral over A x B of
// f cos cos, estimated from the run with incidence spread over A (qab) and from the run with
// incidence spread over B (qba).
struct RecipPair {
    double alpha = 0, eta = 0;
    int prism = 0, a = 0, b = 0;
    sim::Estimate qab, qba;
};

struct Reciprocity {
    std::vector<double> z, rel; // simulation: z-scores and relative differences of the pairs
    std::array<std::vector<double>, 4> wide, near; // variants: relative asymmetries
};

std::vector<RecipPair> reciprocity_runs(double alpha, double eta, int prism, std::uint64_t rays,
                                        std::uint64_t seed, int threads, double& seconds,
                                        double& raysDone) {
    const std::vector<ProbeDir> dirs = probe_dirs();
    const double r = kRecipConeDeg * kDeg;
    const sim::Sheet sheet =
        sim::sheet_from_params(config_params(Config{0, alpha, eta, prism}, 0), 0);
    std::vector<sim::Grid> cones;
    for (const ProbeDir& d : dirs)
        cones.push_back(sim::cone_grid("cone", direction_deg(d.theta, d.phi), r));
    std::vector<std::vector<sim::Estimate>> q(dirs.size(), std::vector<sim::Estimate>(dirs.size()));
    for (size_t a = 0; a < dirs.size(); ++a) {
        ProgressBar bar("[reciprocity] " + key_of(alpha, eta, prism) +
                        fmt(" from theta %g", dirs[a].theta) + fmt(" phi %g", dirs[a].phi));
        sim::RunOptions opt;
        opt.rays = rays;
        opt.seed = seed + a;
        opt.threads = threads;
        opt.incidence_cone = r;
        opt.progress = [&bar](std::uint64_t d, std::uint64_t n) { bar(d, n); };
        const dvec3 wa = direction_deg(dirs[a].theta, dirs[a].phi);
        const sim::Run run = sim::simulate(sheet, wa, cones, opt);
        seconds += run.seconds;
        raysDone += double(run.tally.rays);
        // Omega_p(A) = pi sin^2 r cos(theta_A) for a cone above the horizon.
        const double projA = kPi * std::sin(r) * std::sin(r) * wa.z;
        for (size_t b = 0; b < dirs.size(); ++b) {
            const std::uint64_t* k = &run.tally.counts[b][0];
            sim::Estimate e =
                sim::fraction(k[sim::kSurface] + k[sim::kRetro] + k[sim::kDiffuse], run.tally.rays);
            e.value *= projA;
            e.se *= projA;
            q[a][b] = e;
        }
    }
    std::vector<RecipPair> out;
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
            out.push_back(p);
        }
    return out;
}

double median(std::vector<double> v) {
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

std::vector<double> abs_of(std::vector<double> v) {
    for (double& x : v)
        x = std::abs(x);
    return v;
}

std::string key_of(double alpha, double eta, int prism) {
    return fmt("%g", alpha) + "/" + fmt("%g", eta) + "/" + prism_name(prism);
}

// The study's results as a flat list of numbers (save with --save, reuse with --load to redo the
// tables and plots without simulating again). The first lines are the machine and date of the run.
struct Archive {
    bool loading = false;
    std::vector<double> data;
    size_t pos = 0;
    void io(double& v) {
        if (loading) {
            if (pos >= data.size()) throw InputError("--load: the results file is truncated");
            v = data[pos++];
        } else {
            data.push_back(v);
        }
    }
    void io(int& v) {
        double d = v;
        io(d);
        v = int(d);
    }
    void io(bool& v) {
        double d = v ? 1 : 0;
        io(d);
        v = d != 0;
    }
    void io(std::uint64_t& v) {
        double d = double(v);
        io(d);
        v = std::uint64_t(d);
    }
    void io(sim::Estimate& e) {
        io(e.value);
        io(e.se);
    }
    void io(sim::LobeFit& f) {
        io(f.ok);
        io(f.ax);
        io(f.ay);
        io(f.se_ax);
        io(f.se_ay);
        io(f.mx);
        io(f.my);
        io(f.cells);
        io(f.chi2_reduced);
    }
    template <class T>
    void io(std::vector<T>& v) {
        std::uint64_t n = v.size();
        io(n);
        if (loading) v.resize(size_t(n));
        for (T& x : v)
            io(x);
    }
    void io(SimResult& s) {
        io(s.rays);
        io(s.seconds);
        io(s.threads);
        io(s.fit);
        for (sim::Estimate* e :
             {&s.peak, &s.energy, &s.energyPrimary, &s.energyMultiple, &s.diffuseNormal,
              &s.diffuse60, &s.diffuseAlbedo, &s.surface, &s.surfaceSingle, &s.absorbed})
            io(*e);
        io(s.trapped);
        io(s.l1Noise);
        io(s.l1RetroNoise);
        io(s.rowX);
        io(s.colX);
        io(s.stripX);
        io(s.row);
        io(s.col);
        for (auto& v : s.strip)
            io(v);

        io(s.hx);
        io(s.hy);
    }
    void io(VariantResult& r) {
        for (double* d : {&r.alphaPar, &r.alphaPerp, &r.peak, &r.energy, &r.surface,
                          &r.diffuseNormal, &r.diffuse60, &r.diffuseAlbedo, &r.l1, &r.l1Retro})
            io(*d);
        io(r.fit);
        io(r.row);
        io(r.col);
        for (auto& v : r.strip)
            io(v);
    }
    void io(RecipPair& p) {
        io(p.alpha);
        io(p.eta);
        io(p.prism);
        io(p.a);
        io(p.b);
        io(p.qab);
        io(p.qba);
    }
    void io(ConfigResult& r) {
        io(r.c.theta);
        io(r.c.alpha);
        io(r.c.eta);
        io(r.c.prism);
        io(r.sim);
        for (VariantResult& v : r.v)
            io(v);
    }
    // The whole study: options, timing and results.
    void io(StudyOptions& so, double& simSeconds, double& simRays, int& threadsUsed,
            double& elapsed, std::vector<ConfigResult>& results, std::vector<ConfigResult>& direct,
            std::vector<RecipPair>& pairs) {
        io(so.rays);
        io(so.diffuseRays);
        io(so.recipRays);
        io(so.seed);
        io(simSeconds);
        io(simRays);
        io(threadsUsed);
        io(elapsed);
        io(results);
        io(direct);
        io(pairs);
    }
};

} // namespace

int cmd_simulate(int argc, const char** argv) {
    // --study hands its arguments to the study.
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--study") == 0) {
            std::vector<std::string> rest;
            for (int k = 1; k < argc; ++k)
                if (k != i) rest.push_back(argv[k]);
            return run_study(rest);
        }
    OIIO::ArgParse ap;
    ap.intro("retroprism simulate: the microgeometry Monte Carlo (MODEL.md section 6): the "
             "tabulated BRDF per lobe with standard errors for each incident direction, as "
             "PREFIX_thetaDEG.exr (one part per grid) and PREFIX.json. `retroprism simulate "
             "--study --help` describes the accuracy study.")
        .usage("retroprism simulate [--material FILE.json] --theta-i DEG... [--phi-i DEG] "
               "[--rays N] [--seed S] [--threads T] [--way-up prisms|direct] [--out PREFIX]");
    std::vector<std::string> thetas;
    ap.arg("--material FILE").help("node inputs as a JSON object (default: all defaults)");
    ap.arg("--theta-i DEG...").help("incident polar angles in degrees, [0, 90)");
    ap.arg("--phi-i DEG")
        .dest("phi_i")
        .help("incident azimuth in degrees (default 0)")
        .defaultval("0");
    ap.arg("--rays N")
        .help("rays per incident direction, [1, 1e12] (default 1000000)")
        .defaultval("1000000");
    ap.arg("--seed S").help("seed of the random streams (default 1)").defaultval("1");
    ap.arg("--threads T").help("threads, [1, 256] (default: all cores)").defaultval("0");
    ap.arg("--way-up MODE")
        .dest("way_up")
        .help("how substrate light crosses the prisms upward: prisms (the adjoint of the way "
              "down, reciprocal; default) or direct (the paper's assumption)")
        .defaultval("prisms");
    ap.arg("--out PREFIX").help("output prefix (default simulate)").defaultval("simulate");
    ap.arg("thetas").hidden().action([&](OIIO::cspan<const char*> a) { thetas.push_back(a[0]); });
    std::vector<const char*> args;
    for (int i = 0; i < argc; ++i)
        if (std::strcmp(argv[i], "--theta-i") != 0) args.push_back(argv[i]);
    ap.exit_on_error(false);
    if (ap.parse_args(int(args.size()), args.data()) < 0) {
        std::fprintf(stderr, "retroprism simulate: %s\n", ap.geterror().c_str());
        return 2;
    }
    if (ap.aborted() || ap["help"].get<int>()) return 0;
    if (thetas.empty()) throw InputError("simulate: --theta-i DEG... is required");
    Params p;
    const std::string file = ap["material"].get<std::string>();
    if (!file.empty()) p = params_from_json(read_json(file), file);
    std::vector<double> angles;
    for (const std::string& s : thetas) {
        const double t = parse_real(s, "--theta-i");
        if (t < 0 || t >= 90) throw InputError("--theta-i " + s + ": must be in [0, 90) degrees");
        angles.push_back(t);
    }
    const double phi = parse_real(ap["phi_i"].get<std::string>(), "--phi-i");
    const std::uint64_t rays = parse_count(ap["rays"].get<std::string>(), "--rays", 1, 1e12);
    const std::uint64_t seed = parse_count(ap["seed"].get<std::string>(), "--seed", 0, 9.0e15);
    const std::string th = ap["threads"].get<std::string>();
    const int threads = th == "0" ? 0 : int(parse_count(th, "--threads", 1, 256));
    const std::string way = ap["way_up"].get<std::string>();
    if (way != "prisms" && way != "direct")
        throw InputError("--way-up " + way + ": expected prisms or direct");
    return simulate_command(p, angles, phi, rays, seed, threads, ap["out"].get<std::string>(),
                            way == "prisms");
}

int run_study(const std::vector<std::string>& argsIn) {
    StudyOptions so;
    for (size_t i = 0; i < argsIn.size(); ++i) {
        const std::string& a = argsIn[i];
        auto value = [&](const char* opt) {
            if (i + 1 >= argsIn.size()) throw InputError(std::string(opt) + ": missing value");
            return argsIn[++i];
        };
        if (a == "--help" || a == "-h") {
            std::printf(
                "retroprism simulate --study [--rays N] [--diffuse-rays N] [--recip-rays N] "
                "[--seed S] "
                "[--threads T] [--doc FILE.md] [--quick]\n\n"
                "The accuracy study: every analytic variant (retro_lobe isotropic|anisotropic x "
                "reciprocal false|true) against the microgeometry simulator for theta_i in {0, 20, "
                "40, 60, 75, 85} deg, roughness in {0.005, 0.02, 0.1, 0.3}, ior in {1.49, 1.586}, "
                "prism_reflection tir and metallized (diffuse_color 0.9, era_mode averaged). "
                "Writes FILE.md (default docs/accuracy.md), its plots and results.csv into the "
                "folder `accuracy` next to it.\n"
                "  --rays N          rays per configuration (default 4000000)\n"
                "  --diffuse-rays N  rays per configuration of the diffuse-model runs with the "
                "paper's way up (default 1000000)\n"
                "  --recip-rays N    rays per cone of incidence of the reciprocity runs "
                "(default 400000)\n"
                "  --seed S          base seed (default 2018; configuration k uses S + k)\n"
                "  --threads T       threads (default: all cores)\n"
                "  --quick           a small subset (theta_i 20 and 60, roughness 0.1, ior 1.49, "
                "tir): a smoke test of the command, not the study\n"
                "  --save FILE       also write the results as numbers to FILE\n"
                "  --load FILE       redo the tables and plots from FILE (written by --save with "
                "the same --quick) instead of simulating\n");
            return 0;
        } else if (a == "--rays") {
            so.rays = parse_count(value("--rays"), "--rays", 1000, 1e12);
        } else if (a == "--recip-rays") {
            so.recipRays = parse_count(value("--recip-rays"), "--recip-rays", 1000, 1e12);
        } else if (a == "--diffuse-rays") {
            so.diffuseRays = parse_count(value("--diffuse-rays"), "--diffuse-rays", 1000, 1e12);
        } else if (a == "--seed") {
            so.seed = parse_count(value("--seed"), "--seed", 0, 9.0e15);
        } else if (a == "--threads") {
            so.threads = int(parse_count(value("--threads"), "--threads", 1, 256));
        } else if (a == "--doc") {
            so.doc = value("--doc");
            if (so.doc.extension() != ".md")
                throw InputError("--doc " + so.doc.string() + ": expected a .md file name");
        } else if (a == "--quick") {
            so.quick = true;
        } else if (a == "--save") {
            so.save = value("--save");
        } else if (a == "--load") {
            so.load = value("--load");
        } else {
            throw InputError("simulate --study: unknown argument " + a +
                             " (see retroprism simulate --study --help)");
        }
    }
    const std::vector<double> thetas = so.quick ? std::vector<double>{20, 60} : kStudyThetas;
    const std::vector<double> alphas = so.quick ? std::vector<double>{0.1} : kStudyAlphas;
    const std::vector<double> etas = so.quick ? std::vector<double>{1.49} : kStudyEtas;
    const std::vector<int> prisms = so.quick ? std::vector<int>{f64::RP_PRISM_TIR} : kStudyPrisms;

    fs::path docDir = so.doc.parent_path();
    if (docDir.empty()) docDir = ".";
    const fs::path plotDir = docDir / "accuracy";
    std::error_code ec;
    fs::create_directories(plotDir, ec);
    if (ec || !fs::is_directory(plotDir))
        throw InputError("--doc " + so.doc.string() + ": cannot create " + plotDir.string());
    check_prefix((plotDir / "probe").string());

    const auto t0 = std::chrono::steady_clock::now();
    std::vector<ConfigResult> results, direct;
    std::vector<RecipPair> pairs;
    std::uint64_t k = 0;
    double simSeconds = 0, simRays = 0, elapsed = 0;
    int threadsUsed = 1;
    const double dAlpha = so.quick ? alphas[0] : kDiffuseAlpha;
    std::string machine = machine_description(), date = today();
    if (so.load.empty()) {
        const std::string loadStart = load_average();
        const size_t total = thetas.size() * alphas.size() * etas.size() * prisms.size();
        for (double eta : etas)
            for (int prism : prisms)
                for (double alpha : alphas)
                    for (double theta : thetas) {
                        const Config c{theta, alpha, eta, prism};
                        const std::string label = fmt("[%.0f/", double(results.size() + 1)) +
                                                  fmt("%.0f] ", double(total)) + config_label(c);
                        results.push_back(
                            run_config(c, so.rays, so.seed + k++, true, true, so.threads, label));
                        const ConfigResult& r = results.back();
                        simSeconds += r.sim.seconds;
                        simRays += double(r.sim.rays);
                        threadsUsed = r.sim.threads;
                        std::printf(
                            "%-40s sim: retro %.5f (fit %.4f %.4f) diffuse(n) %.4f | "
                            "widths %s %s | energy %s %s %s %s  (%.1f s)\n",
                            config_label(c).c_str(), r.sim.energy.value, r.sim.fit.ax, r.sim.fit.ay,
                            r.sim.diffuseNormal.value, pct(width_err(r, 0, true)).c_str(),
                            pct(width_err(r, 1, true)).c_str(),
                            pct(r.v[0].energy / r.sim.energy.value - 1).c_str(),
                            pct(r.v[1].energy / r.sim.energy.value - 1).c_str(),
                            pct(r.v[2].energy / r.sim.energy.value - 1).c_str(),
                            pct(r.v[3].energy / r.sim.energy.value - 1).c_str(), r.sim.seconds);
                        std::fflush(stdout);
                    }
        // The paper's way up (substrate light straight to the top surface), for the diffuse lobe.
        for (double eta : etas)
            for (int prism : prisms)
                for (double theta : thetas) {
                    const Config c{theta, dAlpha, eta, prism};
                    direct.push_back(run_config(c, so.diffuseRays, so.seed + 100000 + k++, false,
                                                false, so.threads,
                                                "[way up direct] " + config_label(c)));
                    simSeconds += direct.back().sim.seconds;
                    simRays += double(direct.back().sim.rays);
                }

        // Reciprocity: cone-to-cone runs for every material.
        std::uint64_t m = 0;
        for (double eta : etas)
            for (int prism : prisms)
                for (double alpha : alphas) {
                    const std::vector<RecipPair> rp = reciprocity_runs(
                        alpha, eta, prism, so.recipRays, so.seed + 200000 + 100 * m++, so.threads,
                        simSeconds, simRays);
                    pairs.insert(pairs.end(), rp.begin(), rp.end());
                }
        elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        machine += "; 1-minute load average " + loadStart + " at the start and " + load_average() +
                   " at the end of the simulations (above the number of hardware threads, "
                   "other processes shared the cores and the rays/s below are lower than on an "
                   "idle machine)";
    } else {
        std::ifstream in(so.load);
        if (!in) throw InputError("--load " + so.load + ": cannot open file");
        std::getline(in, machine);
        std::getline(in, date);
        Archive ar;
        ar.loading = true;
        std::string tok;
        while (in >> tok)
            ar.data.push_back(std::strtod(tok.c_str(), nullptr));
        ar.io(so, simSeconds, simRays, threadsUsed, elapsed, results, direct, pairs);
        const size_t expected = thetas.size() * alphas.size() * etas.size() * prisms.size();
        if (results.size() != expected)
            throw InputError("--load " + so.load + ": " + std::to_string(results.size()) +
                             " configurations, expected " + std::to_string(expected) +
                             " (the same --quick as the run that saved it)");
    }
    if (!so.save.empty()) {
        Archive ar;
        ar.io(so, simSeconds, simRays, threadsUsed, elapsed, results, direct, pairs);
        std::ofstream out(so.save);
        out << machine << "\n" << date << "\n";
        char buf[40];
        for (double d : ar.data) {
            std::snprintf(buf, sizeof buf, "%.17g\n", d);
            out << buf;
        }
        if (!out) throw InputError("--save " + so.save + ": cannot write");
    }
    std::map<std::string, size_t> index; // "theta/alpha/eta/prism" -> result
    for (size_t i = 0; i < results.size(); ++i)
        index[fmt("%g/", results[i].c.theta) +
              key_of(results[i].c.alpha, results[i].c.eta, results[i].c.prism)] = i;

    // ---- Reciprocity ----
    Reciprocity rec;
    const std::vector<ProbeDir> dirs = probe_dirs();
    // z of a pair with the standard error under the hypothesis Q(A, B) = Q(B, A) = their mean
    // Q: the count of the run over A is binomial with mean N Q / Omega_p(A), so
    // var(Q_ab) = Omega_p(A) Q (1 - Q / Omega_p(A)) / N. (The errors of the observed counts
    // would understate the variance of low counts that fluctuated down.)
    auto zOf = [&](const RecipPair& q) {
        const double r = kRecipConeDeg * kDeg;
        const double oa =
            kPi * std::sin(r) * std::sin(r) * direction_deg(dirs[size_t(q.a)].theta, 0).z;
        const double ob =
            kPi * std::sin(r) * std::sin(r) * direction_deg(dirs[size_t(q.b)].theta, 0).z;
        const double mean = 0.5 * (q.qab.value + q.qba.value);
        const double n = double(so.recipRays);
        const double var = (oa * mean * (1 - mean / oa) + ob * mean * (1 - mean / ob)) / n;
        return var > 0 ? (q.qab.value - q.qba.value) / std::sqrt(var) : 0.0;
    };
    for (const RecipPair& p : pairs) {
        if (!(p.qab.value + p.qba.value > 0)) continue;
        rec.z.push_back(zOf(p));
        rec.rel.push_back((p.qab.value - p.qba.value) / (0.5 * (p.qab.value + p.qba.value)));
    }
    for (double eta : etas)
        for (int prism : prisms)
            for (double alpha : alphas) {
                const std::string key = key_of(alpha, eta, prism);
                std::vector<Params> vp;
                for (int v = 0; v < 4; ++v)
                    vp.push_back(config_params(Config{0, alpha, eta, prism}, v));
                for (size_t a = 0; a < dirs.size(); ++a)
                    for (size_t b = a + 1; b < dirs.size(); ++b) {
                        const dvec3 wa = direction_deg(dirs[a].theta, dirs[a].phi);
                        const dvec3 wb = direction_deg(dirs[b].theta, dirs[b].phi);
                        for (int v = 0; v < 4; ++v) {
                            const PrismaticRetroreflector<double> node(vp[size_t(v)]);
                            const double x = node.eval(wa, wb).f.total().x;
                            const double y = node.eval(wb, wa).f.total().x;
                            if (x + y > 1e-12)
                                rec.wide[size_t(v)].push_back(std::abs(x - y) / (0.5 * (x + y)));
                        }
                    }
                for (double theta : thetas) {
                    const dvec3 wi = direction_deg(theta, 0);
                    dvec3 ePar, ePerp;
                    sim::lobe_frame(wi, ePar, ePerp);
                    const double aIso = results[index[fmt("%g/", theta) + key]].v[0].alphaPar;
                    for (int v = 0; v < 4; ++v) {
                        const PrismaticRetroreflector<double> node(vp[size_t(v)]);
                        for (double d : {0.5, 1.0, 2.0})
                            for (const dvec3& e : {ePar, -ePar, ePerp}) {
                                const dvec3 wo = glm::normalize(wi + d * aIso * e);
                                if (wo.z < 0.02) continue;
                                const double x = node.eval(wi, wo).f.total().x;
                                const double y = node.eval(wo, wi).f.total().x;
                                if (x + y > 1e-12)
                                    rec.near[size_t(v)].push_back(std::abs(x - y) /
                                                                  (0.5 * (x + y)));
                            }
                    }
                }
            }

    // ---- CSV of every figure ----
    {
        std::ofstream csv(plotDir / "results.csv");
        csv << "theta_i_deg,roughness,ior,prism_reflection,rays,sim_seconds,"
               "sim_retro_peak,sim_retro_peak_se,sim_fit_alpha_par,sim_fit_alpha_par_se,"
               "sim_fit_alpha_perp,sim_fit_alpha_perp_se,sim_fit_shift_par,sim_retro_energy,"
               "sim_retro_energy_se,sim_retro_primary,sim_retro_multiple,sim_diffuse_normal,"
               "sim_diffuse_normal_se,sim_diffuse_60_90,sim_diffuse_60_90_se,sim_diffuse_albedo,"
               "sim_surface,sim_surface_single,sim_absorbed,sim_trapped,sim_l1_noise,"
               "sim_l1_retro_noise,retro_grid_half_par,retro_grid_half_perp";
        for (const Variant& v : kVariants)
            for (const char* f : {"alpha_par", "alpha_perp", "fit_alpha_par", "fit_alpha_perp",
                                  "retro_peak", "retro_energy", "surface", "diffuse_normal",
                                  "diffuse_60_90", "diffuse_albedo", "l1", "l1_retro"})
                csv << "," << v.key << "_" << f;
        csv << "\n";
        for (const ConfigResult& r : results) {
            const SimResult& s = r.sim;
            csv << r.c.theta << "," << r.c.alpha << "," << r.c.eta << "," << prism_name(r.c.prism)
                << "," << s.rays << "," << s.seconds << "," << s.peak.value << "," << s.peak.se
                << "," << s.fit.ax << "," << s.fit.se_ax << "," << s.fit.ay << "," << s.fit.se_ay
                << "," << s.fit.mx << "," << s.energy.value << "," << s.energy.se << ","
                << s.energyPrimary.value << "," << s.energyMultiple.value << ","
                << s.diffuseNormal.value << "," << s.diffuseNormal.se << "," << s.diffuse60.value
                << "," << s.diffuse60.se << "," << s.diffuseAlbedo.value << "," << s.surface.value
                << "," << s.surfaceSingle.value << "," << s.absorbed.value << "," << s.trapped
                << "," << s.l1Noise << "," << s.l1RetroNoise << "," << s.hx << "," << s.hy;
            for (const VariantResult& v : r.v)
                csv << "," << v.alphaPar << "," << v.alphaPerp << "," << v.fit.ax << "," << v.fit.ay
                    << "," << v.peak << "," << v.energy << "," << v.surface << ","
                    << v.diffuseNormal << "," << v.diffuse60 << "," << v.diffuseAlbedo << ","
                    << v.l1 << "," << v.l1Retro;
            csv << "\n";
        }
        if (!csv) throw InputError((plotDir / "results.csv").string() + ": cannot write");
    }

    std::vector<std::string> pngs;
    for (double eta : etas)
        for (int prism : prisms)
            for (const char* kindName : {"retro_inplane_", "retro_across_", "slices_"})
                pngs.push_back(kindName + fmt("eta%g_", eta) + prism_name(prism) + ".png");
    // ---- The document ----
    std::ostringstream md;
    const std::string rel = plotDir.filename().string();
    md << "# Accuracy of the analytic model against the microgeometry simulator\n\n";
    md << "Generated by `retroprism simulate --study" << (so.quick ? " --quick" : "") << " --rays "
       << so.rays << " --diffuse-rays " << so.diffuseRays << " --recip-rays " << so.recipRays
       << " --seed " << so.seed
       << (so.doc != "docs/accuracy.md" ? " --doc " + so.doc.string() : std::string())
       << "`, run from the repository root (with the build's `retroprism`, e.g. "
          "`build/cli/retroprism`). Do not edit by hand: rerun the command.\n\n";
    md << "- Date: " << date << "; machine: " << machine << ".\n";
    md << "- Rays: " << so.rays << " per configuration (" << results.size()
       << " configurations), and " << so.diffuseRays << " per configuration for the "
       << direct.size() << " runs of the paper's way up (section 5), and " << so.recipRays
       << " per cone of incidence for the " << pairs.size() / 55 * 11
       << " reciprocity runs (section 6). Total " << fmt("%.4g", simRays) << " rays in "
       << fmt("%.0f", simSeconds) << " s of simulation: **" << fmt("%.3g", simRays / simSeconds)
       << " rays/s on " << threadsUsed << " threads** ("
       << fmt("%.3g", simRays / simSeconds / threadsUsed) << " per thread); the whole study took "
       << fmt("%.1f", elapsed / 60) << " min.\n";
    md << "- Every figure of this page is in [`" << rel << "/results.csv`](" << rel
       << "/results.csv), one row per configuration.\n\n";
    md << "@@FINDINGS@@";
    md << "## What is compared\n\n"
          "The **simulator** (`sim/microgeometry.h`, `retroprism simulate`) traces light through "
          "the explicit microgeometry in geometric optics: the rough top surface is crossed by the "
          "Smith random walk of Heitz et al. 2016 (visible Beckmann microfacets, exact Fresnel "
          "choice, repeated hits until the ray leaves, so nothing is lost there and multiple "
          "scattering is included; its single-scattering part is exactly the analytic surface "
          "lobe), refracted rays meet a cube corner at a uniform point of its aperture (random "
          "orientation per encounter: the `averaged` ERA mode) and are traced exactly (TIR faces: "
          "internal Fresnel per hit, transmitted light goes to the substrate; metallized faces: "
          "reflectance 0.88 per hit, the rest absorbed), non-retroreflected light goes to the "
          "Lambertian substrate (k_d = 0.9), and substrate light crosses the prism layer upward as "
          "the exact adjoint of the way down (so the simulated BRDF is reciprocal; section 5 also "
          "runs the paper's assumption, substrate light straight to the top surface). Internal "
          "reflections at the top surface send light back down to the prisms.\n\n"
          "The **analytic variants** are the node (`nodes/prism_core.inc`) with `retro_lobe` "
          "isotropic or anisotropic and `reciprocal` false or true; everything else fixed: "
          "`diffuse_color` 0.9, `era_mode` averaged, `specular` 1, `metal_reflectance` 0.88.\n\n"
          "Configurations: theta_i in {0, 20, 40, 60, 75, 85} deg, roughness alpha in {0.005, "
          "0.02, 0.1, 0.3}, ior in {1.49, 1.586}, prisms tir and metallized.\n\n"
          "### What each number means\n\n"
          "All comparisons are made on the same cells: the simulator histograms exit directions, "
          "and the analytic BRDF is integrated over the same cells (midpoint rule refined near "
          "the narrow lobes), so both sides are cosine-weighted cell averages.\n\n"
          "- **Retro grid**: a gnomonic grid of 41 x 41 cells of slopes about wi, axes in the "
          "plane of incidence (toward the horizon) and across it, half-widths 4 times the widest "
          "analytic retro width (at most slope 3).\n"
          "- **Lobe width error** (along / across the plane of incidence): a Gaussian in slopes, "
          "log f = c + linear terms - x^2/a_par^2 - y^2/a_perp^2, is fitted by weighted least "
          "squares (weights: the cells' counts) to the simulated retro lobe over the cells with "
          "at least 16 rays, within e^-3 of the peak and at least half above the horizon; the "
          "same fit on the same cells with the same weights is applied to each variant's cell "
          "averages. Error = a_variant / a_sim - 1. The fitted a of a Beckmann lobe is its alpha "
          "(the analytic lobe is exactly Gaussian in these slopes up to its T(theta_o) G1(theta_o) "
          "factors), so it can be compared with the variants' alpha_o, alpha_par, alpha_perp "
          "(section 3).\n"
          "- **Retro energy error**: the variant's integral of f_r cos theta_o over the hemisphere "
          "(its retro albedo) / the simulated fraction of rays that leave after retroreflection "
          "without reaching the substrate - 1.\n"
          "- **Retro peak error**: f_r at the retro direction: its average over the 3 x 3 cells "
          "of the retro grid about wi (+-0.29 of the widest analytic width), variant / "
          "simulation - 1.\n"
          "- **Diffuse level error**: f_d averaged over a 5-degree cone about the normal, variant "
          "/ "
          "simulation - 1.\n"
          "- **L1**: the relative L1 error of the whole BRDF, sum over the 48 x 48 equal-area "
          "cells "
          "of the hemisphere (each pi/2304 sr of projected solid angle) of |E_variant - E_sim| / "
          "sum of E_sim, E = the cell's integral of f cos theta_o: the fraction of the reflected "
          "light put in the wrong place at that resolution. Its **noise floor** (what a perfect "
          "model would score against this simulation) is given next to it.\n"
          "- A metric counts as **resolved** when the simulation knows it to "
       << fmt("%.0f", 100 * kResolvedSe)
       << "% (standard error of the simulated value, or of the fitted width); worst values are "
          "over resolved configurations, and the number left out is stated. Unresolved cases are "
          "mostly the retro lobe of tir prisms at theta_i >= 60 deg, where the simulated retro "
          "fraction is below 1e-3.\n\n";

    // 1. Headline.
    const double limits[2] = {60, 85};
    md << "## 1. Worst errors of each variant\n\n"
          "Worst over all resolved configurations with theta_i <= 60 deg and <= 85 deg "
          "(signed: + means the variant is larger than the simulation). Lobe width: the worse of "
          "along and across the plane of incidence. Diffuse level: worst over every theta_i, "
          "per prism mode, against the simulator's reciprocal way up (section 5 compares both "
          "ways up).\n\n";
    md << "| variant | width, theta_i <= 60 | width, <= 85 | retro energy, <= 60 | retro energy, "
          "<= 85 | retro peak, <= 60 | retro peak, <= 85 | diffuse at n, tir | diffuse at n, "
          "metallized | L1 median / worst, <= 60 | L1 median / worst, <= 85 |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::array<std::array<Worst, 2>, 4> wWidth, wEnergy, wPeak, wDiff, wPar, wPerp;
    std::array<std::array<std::vector<double>, 2>, 4> l1s;
    for (const ConfigResult& r : results)
        for (int v = 0; v < 4; ++v)
            for (int L = 0; L < 2; ++L) {
                if (r.c.theta > limits[L]) continue;
                const std::string where = config_label(r.c);
                const double ep = width_err(r, v, true), eq = width_err(r, v, false);
                wPar[size_t(v)][size_t(L)].add(ep, width_resolved(r.sim, true), where);
                wPerp[size_t(v)][size_t(L)].add(eq, width_resolved(r.sim, false), where);
                wWidth[size_t(v)][size_t(L)].add(ep, width_resolved(r.sim, true),
                                                 where + ", along");
                wWidth[size_t(v)][size_t(L)].add(eq, width_resolved(r.sim, false),
                                                 where + ", across");
                wEnergy[size_t(v)][size_t(L)].add(r.v[size_t(v)].energy / r.sim.energy.value - 1,
                                                  rel_se(r.sim.energy) <= kResolvedSe, where);
                wPeak[size_t(v)][size_t(L)].add(r.v[size_t(v)].peak / r.sim.peak.value - 1,
                                                rel_se(r.sim.peak) <= kResolvedSe, where);
                // Diffuse level: every theta_i, one column per prism mode.
                if (L == 1)
                    wDiff[size_t(v)][r.c.prism == f64::RP_PRISM_TIR ? 0 : 1].add(
                        r.v[size_t(v)].diffuseNormal / r.sim.diffuseNormal.value - 1,
                        rel_se(r.sim.diffuseNormal) <= kResolvedSe, where);
                l1s[size_t(v)][size_t(L)].push_back(r.v[size_t(v)].l1);
            }
    for (int v = 0; v < 4; ++v) {
        md << "| " << kVariants[v].name;
        for (auto* w : {&wWidth, &wEnergy, &wPeak, &wDiff})
            for (int L = 0; L < 2; ++L)
                md << " | " << (*w)[size_t(v)][size_t(L)].str();
        for (int L = 0; L < 2; ++L)
            md << " | " << fmt("%.3f", median(l1s[size_t(v)][size_t(L)])) << " / "
               << fmt("%.3f", max_abs(l1s[size_t(v)][size_t(L)]));
        md << " |\n";
    }
    std::vector<double> noise60, noise85;
    for (const ConfigResult& r : results) {
        if (r.c.theta <= 60) noise60.push_back(r.sim.l1Noise);
        noise85.push_back(r.sim.l1Noise);
    }
    md << "\nL1 noise floor of the simulation: median " << fmt("%.3f", median(noise60))
       << " (theta_i <= 60), " << fmt("%.3f", median(noise85)) << " (all); worst "
       << fmt("%.3f", max_abs(noise85)) << ".\n\n";
    md << "Where the worst values are, and how many configurations were resolved "
          "(counted / left out):\n\n";
    md << "| variant | metric | theta_i <= 60 | theta_i <= 85 |\n|---|---|---|---|\n";
    for (int v = 0; v < 4; ++v) {
        const std::pair<const char*, std::array<std::array<Worst, 2>, 4>*> rows[] = {
            {"width along", &wPar},
            {"width across", &wPerp},
            {"retro energy", &wEnergy},
            {"retro peak", &wPeak},
            {"diffuse at n (columns: tir / metallized, every theta_i)", &wDiff}};
        for (const auto& row : rows) {
            md << "| " << kVariants[v].name << " | " << row.first;
            for (int L = 0; L < 2; ++L) {
                const Worst& w = (*row.second)[size_t(v)][size_t(L)];
                md << " | " << w.str(true) << " [" << w.counted << " / " << w.unresolved << "]";
            }
            md << " |\n";
        }
    }

    // 2. Per incidence angle.
    md << "\n## 2. Per incidence angle\n\n"
          "Worst lobe-width error (along / across) and worst retro-energy error at each theta_i, "
          "over roughness, ior and prism mode (resolved configurations).\n\n";
    md << "| theta_i |";
    for (const Variant& v : kVariants)
        md << " " << v.name << ": width along / across | energy |";
    md << "\n|---|";
    for (int v = 0; v < 4; ++v)
        md << "---|---|";
    md << "\n";
    for (double theta : thetas) {
        md << "| " << theta;
        for (int v = 0; v < 4; ++v) {
            Worst a, b, e;
            for (const ConfigResult& r : results) {
                if (r.c.theta != theta) continue;
                a.add(width_err(r, v, true), width_resolved(r.sim, true), "");
                b.add(width_err(r, v, false), width_resolved(r.sim, false), "");
                e.add(r.v[size_t(v)].energy / r.sim.energy.value - 1,
                      rel_se(r.sim.energy) <= kResolvedSe, "");
            }
            md << " | " << a.str() << " / " << b.str() << " | " << e.str();
        }
        md << " |\n";
    }

    // 3. Width formulas.
    md << "\n## 3. The lobe-width formulas against the simulation\n\n"
          "The simulated retro lobe's fitted widths divided by the anisotropic formulas of "
          "MODEL.md section 3, alpha_par = sqrt(2) alpha |eta cos theta_t - cos theta_i| / cos "
          "theta_i along the plane of incidence and alpha_perp = sqrt(2) alpha |eta cos theta_t - "
          "cos theta_i| across it (the isotropic alpha_o is their geometric mean), median over ior "
          "and prism mode. In parentheses: the same ratio for the anisotropic variant's own lobe, "
          "fitted on the same cells: it differs from 1 only through the fit (the lobe's "
          "T(theta_o) G1(theta_o) factors and the horizon), so a simulated ratio far from the "
          "parenthesis is the formula's error. `n/a`: not resolved.\n\n";
    md << "| theta_i |";
    for (double a : alphas)
        md << " alpha " << a << ": along | across |";
    md << "\n|---|";
    for (size_t i = 0; i < alphas.size(); ++i)
        md << "---|---|";
    md << "\n";
    for (double theta : thetas) {
        md << "| " << theta;
        for (double alpha : alphas)
            for (int along = 1; along >= 0; --along) {
                std::vector<double> simR, anR;
                for (const ConfigResult& r : results) {
                    if (r.c.theta != theta || r.c.alpha != alpha) continue;
                    if (!width_resolved(r.sim, along != 0) || !r.v[1].fit.ok) continue;
                    const double formula = along ? r.v[1].alphaPar : r.v[1].alphaPerp;
                    simR.push_back((along ? r.sim.fit.ax : r.sim.fit.ay) / formula);
                    anR.push_back((along ? r.v[1].fit.ax : r.v[1].fit.ay) / formula);
                }
                md << " | "
                   << (simR.empty()
                           ? std::string("n/a")
                           : fmt("%.3f", median(simR)) + " (" + fmt("%.3f", median(anR)) + ")");
            }
        md << " |\n";
    }
    md << "\nThe isotropic alpha_o = sqrt(alpha_par alpha_perp) is therefore too narrow along "
          "the plane of incidence and too wide across it by the square root of cos theta_i "
          "wherever the anisotropic pair holds (sections 1 and 2).\n";

    // 4. Retro energy.
    md << "\n## 4. Retro energy\n\n"
          "The retro albedo of the simulation and of the paper's form (isotropic, not "
          "reciprocal), per theta_i and roughness, averaged over ior (both prism modes listed). "
          "`multiple` is the share of the simulated retro energy that went through more than one "
          "retroreflection (internal reflection at the top surface sends it back to the prisms); "
          "the analytic lobe has none.\n\n";
    md << "| prisms | theta_i | alpha | sim retro albedo | paper form | error | multiple |\n"
          "|---|---|---|---|---|---|---|\n";
    for (int prism : prisms)
        for (double theta : thetas)
            for (double alpha : alphas) {
                double s = 0, a = 0, mult = 0;
                int n = 0;
                for (double eta : etas) {
                    const ConfigResult& r =
                        results[index[fmt("%g/", theta) + key_of(alpha, eta, prism)]];
                    s += r.sim.energy.value;
                    a += r.v[0].energy;
                    mult += r.sim.energyMultiple.value;
                    ++n;
                }
                md << "| " << prism_name(prism) << " | " << theta << " | " << alpha << " | "
                   << fmt("%.4g", s / n) << " | " << fmt("%.4g", a / n) << " | "
                   << (s > 0 ? pct(a / s - 1) : "n/a") << " | "
                   << (s > 0 ? fmt("%.1f%%", 100 * mult / s) : "n/a") << " |\n";
            }

    // 5. Diffuse.
    md << "\n## 5. The diffuse lobe: paper form, reciprocal form, simulation\n\n"
          "f_d at the normal (5-degree cone) and at theta_o = 60 deg across the plane of incidence "
          "(phi_o = 90 deg), and the diffuse albedo, at roughness "
       << dAlpha
       << ". `sim, prisms`: the simulator with substrate light crossing the prisms upward (the "
          "adjoint of the way down: reciprocal); `sim, direct`: the paper's assumption (substrate "
          "light straight to the top surface, (1 - E) at entry only). `paper`: T_i T_o (1 - "
          "E_i) k_d / (pi eta^2 (1 - k_d F_dr)); `recip.`: the same with sqrt((1 - E_i)(1 - "
          "E_o)).\n\n";
    md << "| ior | prisms | theta_i | f_d(n): sim, prisms | sim, direct | paper | recip. | "
          "f_d(60,90): sim, prisms | sim, direct | paper | recip. | albedo: sim, prisms | sim, "
          "direct | analytic (both forms) "
          "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::array<std::vector<double>, 4>
        logErr; // paper vs prisms, recip vs prisms, paper vs direct, recip vs direct
    {
        size_t di = 0;
        for (double eta : etas)
            for (int prism : prisms)
                for (double theta : thetas) {
                    const ConfigResult& r =
                        results[index[fmt("%g/", theta) + key_of(dAlpha, eta, prism)]];
                    const ConfigResult& d = direct[di++];
                    md << "| " << eta << " | " << prism_name(prism) << " | " << theta << " | "
                       << fmt("%.4f", r.sim.diffuseNormal.value) << " | "
                       << fmt("%.4f", d.sim.diffuseNormal.value) << " | "
                       << fmt("%.4f", r.v[0].diffuseNormal) << " | "
                       << fmt("%.4f", r.v[2].diffuseNormal) << " | "
                       << fmt("%.4f", r.sim.diffuse60.value) << " | "
                       << fmt("%.4f", d.sim.diffuse60.value) << " | "
                       << fmt("%.4f", r.v[0].diffuse60) << " | " << fmt("%.4f", r.v[2].diffuse60)
                       << " | " << fmt("%.4f", r.sim.diffuseAlbedo.value) << " | "
                       << fmt("%.4f", d.sim.diffuseAlbedo.value) << " | "
                       << fmt("%.4f", r.v[0].diffuseAlbedo) << " / "
                       << fmt("%.4f", r.v[2].diffuseAlbedo) << " |\n";
                    for (int which = 0; which < 2; ++which) {
                        const double sN =
                            which == 0 ? r.sim.diffuseNormal.value : d.sim.diffuseNormal.value;
                        const double s6 =
                            which == 0 ? r.sim.diffuse60.value : d.sim.diffuse60.value;
                        for (int form = 0; form < 2; ++form) {
                            const VariantResult& a = r.v[size_t(form == 0 ? 0 : 2)];
                            logErr[size_t(which * 2 + form)].push_back(
                                std::log(a.diffuseNormal / sN));
                            logErr[size_t(which * 2 + form)].push_back(std::log(a.diffuse60 / s6));
                        }
                    }
                }
    }
    auto rms = [](const std::vector<double>& v) {
        double s = 0;
        for (double x : v)
            s += x * x;
        return v.empty() ? NAN : std::sqrt(s / double(v.size()));
    };
    md << "\nRMS of log(analytic / simulated) over the two directions of every row: paper form "
       << fmt("%.3f", rms(logErr[0])) << " and reciprocal form " << fmt("%.3f", rms(logErr[1]))
       << " against `sim, prisms`; paper form " << fmt("%.3f", rms(logErr[2]))
       << " and reciprocal form " << fmt("%.3f", rms(logErr[3])) << " against `sim, direct`. "
       << "Over all " << results.size() << " configurations (section 1) the worst diffuse-level "
       << "error at the normal is " << wDiff[0][0].str() << " (tir) and " << wDiff[0][1].str()
       << " (metallized) for the paper form, " << wDiff[2][0].str() << " and " << wDiff[2][1].str()
       << " for the reciprocal form (against `sim, prisms`).\n";

    // 6. Reciprocity.
    md << "\n## 6. Reciprocity\n\n"
          "Simulation: an exact test, free of the width of the cones. The 11 directions theta in "
       << "{0, 20, 40, 60, 75, 85} deg, phi 0 and 180, each get a cone of half-angle "
       << fmt("%g", kRecipConeDeg) << " deg. For each cone A a run of " << so.recipRays
       << " rays whose incident directions are spread over A with density proportional to cos "
          "theta counts the exits in every other cone B: that estimates Q(A, B) / Omega_p(A), "
          "Q(A, B) = integral over A x B of f(u, w) cos theta_u cos theta_w. Reciprocity makes Q "
          "symmetric, so Q(A, B) from the run over A and Q(B, A) from the run over B must agree "
          "within their standard errors: z = difference / its standard error under that "
          "hypothesis (binomial counts about the pair's mean) is standard normal for a "
          "reciprocal simulator (55 pairs for every roughness, ior and prism mode).\n\n"
          "Variants: relative asymmetry |f(a, b) - f(b, a)| / mean of the node's point values at "
          "the same 55 pairs of directions, and at pairs near the retro peak (wo = wi tilted by "
          "0.5, 1 and 2 alpha_o along and across the plane of incidence, wi at every theta_i).\n\n";
    {
        double chi2 = 0;
        int over3 = 0;
        for (double z : rec.z) {
            chi2 += z * z;
            if (std::abs(z) > 3) ++over3;
        }
        const double n = double(rec.z.size());
        md << "| | pairs | sum z^2 / pairs | max abs z | pairs with abs z > 3 (expected for "
              "standard normal z) | median relative difference | max relative difference |\n"
              "|---|---|---|---|---|---|---|\n";
        md << "| simulation | " << rec.z.size() << " | " << fmt("%.3f", n > 0 ? chi2 / n : NAN)
           << " | " << fmt("%.2f", max_abs(rec.z)) << " | " << over3 << " ("
           << fmt("%.1f", 0.0027 * n) << ") | " << fmt("%.2f%%", 100 * median(abs_of(rec.rel)))
           << " | " << fmt("%.1f%%", 100 * max_abs(rec.rel)) << " |\n\n";
        // The largest deviations, with their pairs.
        std::vector<size_t> order;
        for (size_t i = 0; i < pairs.size(); ++i)
            order.push_back(i);
        std::sort(order.begin(), order.end(), [&](size_t x, size_t y) {
            return std::abs(zOf(pairs[x])) > std::abs(zOf(pairs[y]));
        });
        md << "Largest |z|: ";
        for (size_t i = 0; i < std::min<size_t>(5, order.size()); ++i) {
            const RecipPair& q = pairs[order[i]];
            md << (i ? "; " : "") << fmt("z = %+.2f", zOf(q)) << " ("
               << fmt("theta %g", dirs[size_t(q.a)].theta) << fmt("/%g", dirs[size_t(q.a)].phi)
               << fmt(" and %g", dirs[size_t(q.b)].theta) << fmt("/%g", dirs[size_t(q.b)].phi)
               << ", " << key_of(q.alpha, q.eta, q.prism) << ", Q " << fmt("%.4g", q.qab.value)
               << fmt(" vs %.4g", q.qba.value) << ")";
        }
        md << ".\n\n";
        md << "| variant | wide pairs: median | max | near the retro peak: median | max |\n"
              "|---|---|---|---|---|\n";
        for (int v = 0; v < 4; ++v)
            md << "| " << kVariants[v].name << " | "
               << fmt("%.2f%%", 100 * median(rec.wide[size_t(v)])) << " | "
               << fmt("%.1f%%", 100 * max_abs(rec.wide[size_t(v)])) << " | "
               << fmt("%.2f%%", 100 * median(rec.near[size_t(v)])) << " | "
               << fmt("%.1f%%", 100 * max_abs(rec.near[size_t(v)])) << " |\n";
    }

    // 7. Surface lobe.
    md << "\n## 7. Surface lobe: single and multiple scattering\n\n"
          "The simulator's paths that leave after one scattering event on the top surface are the "
          "analytic surface lobe (height-correlated Smith, the same Fresnel); the rest is the "
          "multiple scattering the analytic model leaves out. Surface albedo, averaged over ior "
          "and prism mode.\n\n";
    md << "| theta_i |";
    for (double a : alphas)
        md << " alpha " << a << ": sim all orders / sim single / analytic |";
    md << "\n|---|";
    for (size_t i = 0; i < alphas.size(); ++i)
        md << "---|";
    md << "\n";
    for (double theta : thetas) {
        md << "| " << theta;
        for (double alpha : alphas) {
            double all = 0, single = 0, an = 0;
            int n = 0;
            for (const ConfigResult& r : results)
                if (r.c.theta == theta && r.c.alpha == alpha) {
                    all += r.sim.surface.value;
                    single += r.sim.surfaceSingle.value;
                    an += r.v[0].surface;
                    ++n;
                }
            md << " | " << fmt("%.4f", all / n) << " / " << fmt("%.4f", single / n) << " / "
               << fmt("%.4f", an / n);
        }
        md << " |\n";
    }

    // 8. Plots.
    md << "\n## 8. Plots\n\n"
          "Per ior and prism mode, one panel per roughness (rows) and theta_i (columns):\n\n"
          "- `retro_inplane_*`: the retro lobe along the plane of incidence (the retro grid's "
          "centre row), f_r against the angle from wi; simulation with +-2 standard errors "
          "(white), the four variants as lines.\n"
          "- `retro_across_*`: the same across the plane of incidence (centre column).\n"
          "- `slices_*`: the whole BRDF in the plane of incidence on a log scale (total and "
          "diffuse), simulation against the paper form and the anisotropic reciprocal variant.\n\n";
    for (const std::string& p : pngs)
        md << "![" << p << "](" << rel << "/" << p << ")\n\n";

    // Appendix.
    md << "## Appendix: every configuration\n\n"
          "Simulated retro albedo, fitted widths (along / across, slopes) and, per variant, the "
          "width errors (along / across) and the retro-energy error. `-`: not resolved.\n\n";
    md << "| theta_i | alpha | ior | prisms | sim retro albedo | sim a_par / a_perp |";
    for (const Variant& v : kVariants)
        md << " " << v.key << " |";
    md << "\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const ConfigResult& r : results) {
        md << "| " << r.c.theta << " | " << r.c.alpha << " | " << r.c.eta << " | "
           << prism_name(r.c.prism) << " | " << fmt("%.4g", r.sim.energy.value) << " | "
           << (r.sim.fit.ok ? fmt("%.4g", r.sim.fit.ax) + " / " + fmt("%.4g", r.sim.fit.ay) : "-")
           << " |";
        for (int v = 0; v < 4; ++v) {
            const bool rp = width_resolved(r.sim, true), rq = width_resolved(r.sim, false);
            const bool re = rel_se(r.sim.energy) <= kResolvedSe;
            md << " " << (rp ? pct(width_err(r, v, true)) : "-") << " / "
               << (rq ? pct(width_err(r, v, false)) : "-") << " / "
               << (re ? pct(r.v[size_t(v)].energy / r.sim.energy.value - 1) : "-") << " |";
        }
        md << "\n";
    }
    // ---- Findings (computed; inserted at the top) ----
    {
        std::ostringstream f;
        // Median over ior and prism mode of a variant's width error at (theta, alpha).
        auto widthMed = [&](int v, double theta, double alpha, bool along) {
            std::vector<double> e;
            for (const ConfigResult& r : results)
                if (r.c.theta == theta && r.c.alpha == alpha && width_resolved(r.sim, along))
                    e.push_back(width_err(r, v, along));
            return median(e);
        };
        auto widthRow = [&](int v, bool along, double alpha) {
            std::string out;
            for (double theta : thetas) {
                if (theta == 0) continue;
                const double e = widthMed(v, theta, alpha, along);
                out += (out.empty() ? "" : ", ") +
                       (std::isfinite(e) ? pct(e) : std::string("n/a")) + fmt(" (%g)", theta);
            }
            return out;
        };
        auto worstOver = [&](int v, double thetaMax, double alphaMax, int metric) {
            Worst w;
            for (const ConfigResult& r : results) {
                if (r.c.theta > thetaMax || r.c.alpha > alphaMax) continue;
                if (metric == 0) {
                    w.add(width_err(r, v, true), width_resolved(r.sim, true), "");
                    w.add(width_err(r, v, false), width_resolved(r.sim, false), "");
                } else {
                    w.add(r.v[size_t(v)].energy / r.sim.energy.value - 1,
                          rel_se(r.sim.energy) <= kResolvedSe, "");
                }
            }
            return w.str();
        };
        f << "## Findings\n\n"
             "Computed from the tables below (signed errors: analytic / simulated - 1; medians "
             "over ior and prism mode; the numbers in parentheses are theta_i in degrees).\n\n";
        for (double alpha : {0.02, 0.3}) {
            if (std::find(alphas.begin(), alphas.end(), alpha) == alphas.end()) continue;
            f << "- **Lobe width, roughness " << alpha << "**. Isotropic alpha_o (paper): along "
              << "the plane of incidence " << widthRow(0, true, alpha) << "; across "
              << widthRow(0, false, alpha) << ". Anisotropic alpha_par / alpha_perp: along "
              << widthRow(1, true, alpha) << "; across " << widthRow(1, false, alpha)
              << ". Anisotropic + reciprocal: along " << widthRow(3, true, alpha) << "; across "
              << widthRow(3, false, alpha) << ".\n";
        }
        f << "- **Retro energy** (worst over resolved configurations): theta_i <= 40 and "
             "roughness <= 0.1: ";
        for (int v = 0; v < 4; ++v)
            f << (v ? ", " : "") << kVariants[v].key << " " << worstOver(v, 40, 0.1, 1);
        f << "; theta_i <= 60, every roughness: ";
        for (int v = 0; v < 4; ++v)
            f << (v ? ", " : "") << kVariants[v].key << " " << worstOver(v, 60, 1, 1);
        f << "; theta_i <= 85: ";
        for (int v = 0; v < 4; ++v)
            f << (v ? ", " : "") << kVariants[v].key << " " << worstOver(v, 85, 1, 1);
        f << ".\n";
        f << "- **Lobe width** (worst of along and across): theta_i <= 40 and roughness <= 0.1: ";
        for (int v = 0; v < 4; ++v)
            f << (v ? ", " : "") << kVariants[v].key << " " << worstOver(v, 40, 0.1, 0);
        f << ".\n";
        const bool recipBetterPrisms = rms(logErr[1]) < rms(logErr[0]);
        const bool paperBetterDirect = rms(logErr[2]) < rms(logErr[3]);
        f << "- **Diffuse lobe**: with the simulator's reciprocal way up (substrate light crosses "
             "the prisms upward and is seen only through the part that does not retroreflect), "
          << (recipBetterPrisms ? "the reciprocal form is closer than the paper's"
                                : "the paper's form is closer than the reciprocal one")
          << " (RMS log ratio " << fmt("%.3f", rms(logErr[1])) << " vs "
          << fmt("%.3f", rms(logErr[0]))
          << "), but neither matches: the simulated f_d follows the product (1 - E_i)(1 - E_o), "
             "with its dip about the normal (section 5). With the paper's own assumption (way up "
             "direct), "
          << (paperBetterDirect ? "the paper's form matches better"
                                : "the reciprocal form matches better")
          << " (RMS log ratio paper " << fmt("%.3f", rms(logErr[2])) << ", reciprocal "
          << fmt("%.3f", rms(logErr[3])) << ").\n";
        {
            // Diffuse albedo (tir prisms): the forms' energy against the simulation.
            std::array<Worst, 3> paper, recip; // roughness <= 0.1 and theta_i <= 75; 0.3; 85
            for (const ConfigResult& r : results) {
                if (r.c.prism != f64::RP_PRISM_TIR || !(r.sim.diffuseAlbedo.value > 0)) continue;
                const int band = r.c.theta > 75 ? 2 : r.c.alpha > 0.1 ? 1 : 0;
                paper[size_t(band)].add(r.v[0].diffuseAlbedo / r.sim.diffuseAlbedo.value - 1, true,
                                        "");
                recip[size_t(band)].add(r.v[2].diffuseAlbedo / r.sim.diffuseAlbedo.value - 1, true,
                                        "");
            }
            f << "- **Diffuse albedo** (tir prisms; worst errors for roughness <= 0.1 and theta_i "
                 "<= 75 / roughness 0.3 and theta_i <= 75 / theta_i 85): paper form "
              << paper[0].str() << " / " << paper[1].str() << " / " << paper[2].str()
              << "; reciprocal form " << recip[0].str() << " / " << recip[1].str() << " / "
              << recip[2].str()
              << ". The paper's (1 - E_i) puts about the simulated amount of light into the "
                 "diffuse lobe at smooth and moderate roughness (the simulator's two ways up give "
                 "almost the same albedo, section 5); the geometric mean of the reciprocal form "
                 "changes that amount.\n";
        }
        {
            std::vector<double> ratio;
            size_t di = 0;
            for (double eta : etas)
                for (int prism : prisms)
                    for (double theta : thetas) {
                        const ConfigResult& d = direct[di++];
                        if (prism != f64::RP_PRISM_METALLIZED) continue;
                        const ConfigResult& r =
                            results[index[fmt("%g/", theta) + key_of(dAlpha, eta, prism)]];
                        if (d.sim.diffuseAlbedo.value > 0)
                            ratio.push_back(r.v[0].diffuseAlbedo / d.sim.diffuseAlbedo.value);
                    }
            if (!ratio.empty())
                f << "- **Metallized prisms**: the analytic diffuse lobe sends the light the metal "
                     "absorbs ((1 - E) includes 1 - R_metal^3 of the retroreflecting part and the "
                     "metal's losses on the other paths) to the substrate; its diffuse albedo is "
                  << fmt("%.2f", median(ratio))
                  << " times the simulated one (median; even with the "
                  << "paper's way up).\n";
        }
        {
            double chi2 = 0;
            for (double z : rec.z)
                chi2 += z * z;
            f << "- **Reciprocity**: the simulation passes the exact test (sum of z^2 / pairs = "
              << fmt("%.3f", rec.z.empty() ? NAN : chi2 / double(rec.z.size())) << " over "
              << rec.z.size() << " pairs, max |z| " << fmt("%.2f", max_abs(rec.z))
              << "). The paper's form is not reciprocal (median asymmetry "
              << fmt("%.1f%%", 100 * median(rec.wide[0])) << " at wide pairs, "
              << fmt("%.1f%%", 100 * median(rec.near[0])) << " near the retro peak, worst "
              << fmt("%.0f%%", 100 * std::max(max_abs(rec.wide[0]), max_abs(rec.near[0])))
              << "); the reciprocal variants are, to rounding.\n";
        }
        {
            double all = 0, single = 0;
            int n = 0;
            for (const ConfigResult& r : results)
                if (r.c.theta == thetas.back() && r.c.alpha == alphas.back()) {
                    all += r.sim.surface.value;
                    single += r.sim.surfaceSingle.value;
                    ++n;
                }
            if (n > 0 && single > 0)
                f << "- **Surface lobe**: the simulator's single scattering reproduces the "
                     "analytic "
                     "surface lobe (section 7); multiple scattering on the rough top surface, "
                     "which the model leaves out, adds "
                  << fmt("%.1f%%", 100 * (all / single - 1)) << " to the surface albedo at theta_i "
                  << thetas.back() << " deg and roughness " << alphas.back() << ".\n";
        }
        f << "\n";
        std::string text = md.str();
        const size_t at = text.find("@@FINDINGS@@");
        if (at != std::string::npos) text.replace(at, 12, f.str());
        md.str(text);
        md.seekp(0, std::ios_base::end);
    }
    const fs::path tmpDoc = so.doc.string() + ".tmp" + std::to_string(getpid());
    {
        std::ofstream f(tmpDoc);
        f << md.str();
        if (!f) throw InputError(so.doc.string() + ": cannot write");
    }
    fs::rename(tmpDoc, so.doc, ec);
    if (ec) throw InputError(so.doc.string() + ": cannot write (" + ec.message() + ")");
    // ---- Plots ----
    Text text;
    for (double eta : etas)
        for (int prism : prisms) {
            const std::string tag = fmt("eta%g_", eta) + prism_name(prism);
            for (int kind = 0; kind < 3; ++kind) {
                Figure fig;
                fig.rows = int(alphas.size());
                fig.cols = int(thetas.size());
                for (double t : thetas)
                    fig.colHeads.push_back(fmt("theta_i = %g deg", t));
                for (double a : alphas)
                    fig.rowHeads.push_back(fmt("alpha %g", a));
                for (double alpha : alphas)
                    for (double theta : thetas) {
                        const ConfigResult& r =
                            results[index[fmt("%g/", theta) + key_of(alpha, eta, prism)]];
                        Panel pan;
                        if (kind < 2) {
                            const std::vector<double>& xs = kind == 0 ? r.sim.rowX : r.sim.colX;
                            const std::vector<sim::Estimate>& es =
                                kind == 0 ? r.sim.row : r.sim.col;
                            pan.x0 = xs.front();
                            pan.x1 = xs.back();
                            for (int v = 0; v < 4; ++v) {
                                Series s;
                                s.x = xs;
                                s.y = kind == 0 ? r.v[size_t(v)].row : r.v[size_t(v)].col;
                                s.color = kVariantCol[v];
                                s.width = v == 0 ? 3 : 2;
                                pan.series.push_back(s);
                            }
                            Series s;
                            s.x = xs;
                            s.color = kSimCol;
                            for (const sim::Estimate& e : es) {
                                s.y.push_back(e.value);
                                s.err.push_back(e.se);
                            }
                            pan.series.push_back(s);
                            pan.title =
                                "fit " + fmt("%.3g", kind == 0 ? r.sim.fit.ax : r.sim.fit.ay) +
                                ", aniso " +
                                fmt("%.3g", kind == 0 ? r.v[1].alphaPar : r.v[1].alphaPerp) +
                                ", iso " + fmt("%.3g", r.v[0].alphaPar);
                        } else {
                            pan.logY = true;
                            pan.x0 = -90;
                            pan.x1 = 90;
                            pan.vlines = {{theta, kVariantCol[0]}, {-theta, kDimCol}};
                            for (int v : {0, 3}) {
                                Series s;
                                s.x = r.sim.stripX;
                                s.y = r.v[size_t(v)].strip[3];
                                s.color = kVariantCol[v];
                                pan.series.push_back(s);
                                Series d;
                                d.x = r.sim.stripX;
                                d.y = r.v[size_t(v)].strip[2];
                                d.color = v == 3 ? kDiffuseRecCol : kDiffuseCol;
                                d.width = 2;
                                pan.series.push_back(d);
                            }
                            for (int l : {3, 2}) {
                                Series s;
                                s.x = r.sim.stripX;
                                s.color = l == 3 ? kSimCol : kDiffuseCol;
                                for (const sim::Estimate& e : r.sim.strip[size_t(l)]) {
                                    s.y.push_back(e.value);
                                    s.err.push_back(e.se);
                                }
                                pan.series.push_back(s);
                            }
                            pan.title = fmt("sim diffuse(n) %.3g", r.sim.diffuseNormal.value) +
                                        fmt(", paper %.3g", r.v[0].diffuseNormal) +
                                        fmt(", recip. %.3g", r.v[2].diffuseNormal);
                        }
                        fig.panels.push_back(pan);
                    }
                const std::string what = kind == 0   ? "in the plane of incidence"
                                         : kind == 1 ? "across the plane of incidence"
                                                     : "whole BRDF in the plane of incidence";
                fig.title = "Retro lobe " + what + ": simulation vs analytic variants (ior " +
                            fmt("%g", eta) + ", " + prism_name(prism) + " prisms, k_d 0.9)";
                if (kind == 2)
                    fig.title = "In-plane slices, log scale: simulation vs analytic (ior " +
                                fmt("%g", eta) + ", " + prism_name(prism) + " prisms, k_d 0.9)";
                if (kind < 2) {
                    fig.xLabel = kind == 0 ? "angle from wi in the plane of incidence [deg] (> 0: "
                                             "toward the horizon)"
                                           : "angle from wi across the plane of incidence [deg]";
                    fig.yLabel =
                        "f_r [1/sr], cosine-weighted cell averages of the retro grid's centre " +
                        std::string(kind == 0 ? "row" : "column");
                    for (int v = 0; v < 4; ++v) {
                        Series s;
                        s.color = kVariantCol[v];
                        s.width = 3;
                        fig.legend.push_back({kVariants[v].name, s});
                    }
                    Series s;
                    s.color = kSimCol;
                    s.err = {0};
                    fig.legend.push_back({"simulation (+-2 se)", s});
                    fig.caption = {
                        "Panel titles: the simulation's fitted Beckmann width along this "
                        "direction, "
                        "and the anisotropic and isotropic variants' widths (slopes).",
                        fmt("%.3g rays per panel; reciprocal variants evaluated as the node does "
                            "(E and the lobe at the mean direction of wi and wo).",
                            double(so.rays))};
                } else {
                    fig.xLabel =
                        "signed theta_o [deg] (> 0: the light's side; retro peak at +theta_i, "
                        "mirror at -theta_i)";
                    fig.yLabel =
                        "f [1/sr] (total and diffuse), 2-degree cells of a 4-degree-wide strip";
                    Series a;
                    a.color = kVariantCol[0];
                    fig.legend.push_back({"total, paper form", a});
                    a.color = kVariantCol[3];
                    fig.legend.push_back({"total, aniso + reciprocal", a});
                    a.color = kDiffuseCol;
                    fig.legend.push_back({"diffuse, paper (1-E_i)", a});
                    a.color = kDiffuseRecCol;
                    fig.legend.push_back({"diffuse, reciprocal sqrt((1-E_i)(1-E_o))", a});
                    Series s;
                    s.color = kSimCol;
                    s.err = {0};
                    fig.legend.push_back({"simulation total", s});
                    s.color = kDiffuseCol;
                    fig.legend.push_back({"simulation diffuse", s});
                    fig.caption = {
                        "Panel titles: the diffuse lobe's f at the normal (5-degree cone), "
                        "simulation vs the paper's form and the reciprocal form."};
                }
                const std::string name = std::string(kind == 0   ? "retro_inplane_"
                                                     : kind == 1 ? "retro_across_"
                                                                 : "slices_") +
                                         tag + ".png";
                write_png(render_figure(fig, text), plotDir / name);
            }
        }

    std::printf("wrote %s, %zu plots and %s in %.1f min (%.3g rays/s on %d threads)\n",
                so.doc.string().c_str(), pngs.size(), (plotDir / "results.csv").string().c_str(),
                elapsed / 60, simRays / simSeconds, threadsUsed);
    return 0;
}

} // namespace retroprism
