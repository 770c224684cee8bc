// cmd_fit.cpp: `retroprism fit DATA.dat`: fits the node, and the MaterialX-style retroreflective
// GGX baseline, to measured BRDF x cos(theta_v) samples in the ALTA text format, and reports both
// side by side. The model, objective, weighting, instrument blur and optimiser are described in
// fitting.h; the baseline's exact formula in nodes/mrm_core.inc (nodes/baselines.h).
//
// Output: a text report (parameters, errors, per-theta_l errors and peak heights, runtime), or
// with --json exactly {"params": {...}, "rel_rms": x, "log_rms": y, "mrm": {"params": {...},
// "rel_rms": x, "log_rms": y}} on standard output; `params` is a material JSON the other
// commands read (inputs not listed keep their defaults). --plot OUT.png writes the in-plane
// slices of each theta_l: measured samples against both fits, log scale.
//
// `retroprism fit --ra TABLE.csv`: fits both to a table of R_A (io/ra_table.h; the fit is
// analysis/ra_fit.h's) and prints measured, fitted and error per entry; --json prints
// {"table", "fitted", "params", "log_rms", "max_error", "entries": [...], "mrm": {"params",
// "log_rms", "max_error"}} (a coloured table: the colour's rows, and "colors": {NAME:
// {"retro_color", "log_rms", "max_error"}}); --plot OUT.png R_A against observation angle per
// entrance angle;
// --mtlx OUT.mtlx [--name NAME] a MaterialX document of the fitted node naming the table and
// the fit's errors. --baseline-only fits the baseline alone (the look-dev page of `retroprism
// view` asks its server for it): --json prints {"table", "mrm": {"params", "log_rms",
// "max_error", "entries": [...]}}.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/argparse.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <nlohmann/json.hpp>

#include "alta_reader.h"
#include "commands.h"
#include "figure.h"
#include "fit_json.h"
#include "fit_plot.h"
#include "fitting.h"
#include "mtlx_writer.h"
#include "parse.h"
#include "plot.h"
#include "query.h"
#include "ra_fit.h"
#include "ra_print.h"
#include "ra_table.h"

namespace fs = std::filesystem;
// Ordered: the keys print in the documented order (params, rel_rms, log_rms, mrm).
using json = nlohmann::ordered_json;

namespace retroprism {

namespace {

constexpr double kDeg = M_PI / 180.0;

using Slice = plot::FitSlice;

std::vector<Slice> slices(const FitData& d, const NodeFit& nf, const MrmFit& mf,
                          const FitOptions& o) {
    std::vector<Slice> out;
    for (size_t g = 0; g < d.group_theta.size(); ++g) {
        Slice sl;
        sl.thetaDeg = d.group_theta[g] / kDeg;
        for (const FitSample& s : d.samples)
            if (size_t(s.group) == g && std::abs(s.wo.y) < 1e-6) {
                const double a = std::atan2(s.wo.x, s.wo.z) / kDeg;
                sl.ms.push_back(a);
                sl.mv.push_back(s.value);
            }
        FitData curve;
        for (int i = -890; i <= 890; ++i)
            sl.s.push_back(0.1 * i);
        for (double peak : {sl.thetaDeg, -sl.thetaDeg})
            for (double dd = 0.01; dd < 4.0; dd *= 1.3) {
                sl.s.push_back(peak - dd);
                sl.s.push_back(peak + dd);
            }
        std::sort(sl.s.begin(), sl.s.end());
        sl.s.erase(
            std::remove_if(sl.s.begin(), sl.s.end(), [](double a) { return std::abs(a) > 89.0; }),
            sl.s.end());
        for (double a : sl.s)
            add_sample(curve, d.group_theta[g],
                       glm::dvec3(std::sin(a * kDeg), 0, std::cos(a * kDeg)), 0.0);
        sl.node = node_values(nf.params, curve, o);
        sl.mrm = mrm_values(mf.model, curve, o);
        sl.nodeRel = nf.report.groups[g].rel_rms;
        sl.nodeLog = nf.report.groups[g].log_rms;
        sl.mrmRel = mf.report.groups[g].rel_rms;
        sl.mrmLog = mf.report.groups[g].log_rms;
        out.push_back(std::move(sl));
    }
    return out;
}

void print_report(const FitData& d, const AltaData& alta, const FitOptions& o, const NodeFit& nf,
                  const MrmFit& mf, double seconds) {
    const std::string sample = alta.header_value("SAMPLE");
    std::printf("data: %s (%zu samples%s), value = BRDF x cos(theta_v) [1/sr]\n", d.file.c_str(),
                d.samples.size(), sample.empty() ? "" : (", \"" + sample + "\"").c_str());
    std::printf("objective: weighted RMS of ln((m + eps) / (y + eps)), eps = %.3g (%.0f%% of the "
                "median value); each theta_l weighs the same, and within it the peak samples (> "
                "%.0f x its median) and the floor weigh half each\n",
                nf.report.epsilon, 100 * o.floor_fraction, o.peak_factor);
    std::printf("instrument: outgoing directions blurred by a Gaussian of FWHM %.3g deg (sigma "
                "%.3g deg), by widening the peaked lobes (fitting.h)\n",
                o.resolution_fwhm_deg, o.resolution_fwhm_deg / 2.3548200450309493);
    const NodeFitParams& p = nf.params;
    const baselines::RetroreflectiveGGX& m = mf.model;
    const char* modes[3] = {"ideal", "tir", "metallized"};
    std::printf("\n%-20s %-30s %-30s\n", "", "node (prismatic retroreflector)",
                "mrm (retroreflective GGX + Lambert)");
    std::printf("%-20s %-30s %-30s\n", "roughness",
                (plot::fmt("%.4f", p.roughness) + " (Beckmann)").c_str(),
                (plot::fmt("%.4f", m.roughness) + " (GGX)").c_str());
    std::printf("%-20s %-30s %-30s\n", "ior",
                (plot::fmt("%.4f", p.ior) + (o.fixed_ior > 0 ? " (fixed)" : "")).c_str(),
                (plot::fmt("%.4f", m.ior) + (o.fixed_ior > 0 ? " (fixed)" : "")).c_str());
    std::printf("%-20s %-30.4f %-30.4f\n", "specular", p.specular, m.specular);
    std::printf("%-20s %-30.4f %-30s\n", "retro_color (grey)", p.retro, "-");
    std::printf("%-20s %-30.4f %-30.4f\n", "diffuse_color (grey)", p.diffuse, m.color.x);
    std::printf("%-20s %-30s %-30s\n", "prism_reflection", modes[p.prism_reflection], "-");
    const char* held = o.paper_geometry ? " (held)" : "";
    std::printf("%-20s %-30s %-30s\n", "cant_angle",
                (plot::fmt("%.4f deg", p.cant_angle) + held).c_str(), "-");
    std::printf("%-20s %-30s %-30s\n", "dihedral_error",
                (plot::fmt("%.4f arcmin", p.dihedral_error) + held).c_str(), "-");
    std::printf("%-20s %-30s %-30s\n", "dihedral_spread",
                (plot::fmt("%.4f arcmin", p.dihedral_spread) + held).c_str(), "-");
    std::printf("%-20s %-30.4f %-30.4f\n", "rel_rms", nf.report.rel_rms, mf.report.rel_rms);
    std::printf("%-20s %-30.4f %-30.4f\n", "log_rms", nf.report.log_rms, mf.report.log_rms);
    std::printf("%-20s %-30.4g %-30.4g\n", "weighted log RMS", std::sqrt(nf.report.objective),
                std::sqrt(mf.report.objective));
    std::printf("%-20s ideal %.4g, tir %.4g, metallized %.4g (weighted RMS log error per "
                "prism_reflection)\n",
                "node modes", std::sqrt(nf.mode_objective[0]), std::sqrt(nf.mode_objective[1]),
                std::sqrt(nf.mode_objective[2]));
    if (!o.paper_geometry)
        std::printf("%-20s ideal %.4g, tir %.4g, metallized %.4g (the same with cant_angle, "
                    "dihedral_error and dihedral_spread 0)\n",
                    "paper geometry", std::sqrt(nf.paper_objective[0]),
                    std::sqrt(nf.paper_objective[1]), std::sqrt(nf.paper_objective[2]));
    std::printf("\nper theta_l (rel_rms and log_rms over that angle's samples; peaks: the highest "
                "measured sample within 3 deg of the retro / mirror direction, and the fits "
                "there):\n");
    std::printf("%8s %6s %9s %9s %9s %9s | %8s %8s %8s | %8s %8s %8s\n", "theta_l", "n", "rel node",
                "rel mrm", "log node", "log mrm", "retro y", "node", "mrm", "mirror y", "node",
                "mrm");
    for (size_t g = 0; g < nf.report.groups.size(); ++g) {
        const GroupReport& a = nf.report.groups[g];
        const GroupReport& b = mf.report.groups[g];
        std::printf("%8.2f %6d %9.4f %9.4f %9.4f %9.4f | %8.4g %8.4g %8.4g | %8.4g %8.4g %8.4g\n",
                    a.theta_deg, a.samples, a.rel_rms, b.rel_rms, a.log_rms, b.log_rms,
                    a.retro_measured, a.retro_model, b.retro_model, a.mirror_measured,
                    a.mirror_model, b.mirror_model);
    }
    std::printf("\nruntime %.1f s (%d + %d shape evaluations)\n", seconds, nf.evaluations,
                mf.evaluations);
}

// ---------------------------------------------------------------------------------------------
// fit --ra

struct RaFitOutputs {
    std::string plot, mtlx, name, color;
    std::vector<std::string> held; // --hold: fittable inputs kept at the base material's value
    RaObjective objective = RaObjective::Rms;
    RaSpectrum spectrum = RaSpectrum::Channels;
    bool json = false;
    bool baselineOnly = false;
};

// --baseline-only: the baseline alone, its parameters and its R_A at every entry.
int fit_ra_baseline(const std::string& file, bool asJson, RaObjective objective) {
    const RaMeasurements t = read_ra_table(file);
    const RaMrmFit mf = fit_ra_mrm(t, objective);
    if (asJson) {
        std::printf("%s\n", ra_baseline_json(t, mf).dump().c_str());
        return 0;
    }
    std::printf("table: %s (%zu rows), R_A [cd lx^-1 m^-2]\n", t.file.c_str(), t.entries.size());
    std::printf("mrm (retroreflective GGX + Lambert): roughness %.6g (GGX), ior %.6g, specular "
                "%.6g\n\n",
                mf.model.roughness, mf.model.ior, mf.model.specular);
    print_ra_comparison(t, {{"mrm", mf.report.model}}, stdout);
    return 0;
}

int fit_ra_table(const std::string& file, const Params& base, const RaFitOutputs& out) {
    if (out.baselineOnly) return fit_ra_baseline(file, out.json, out.objective);
    const auto t0 = std::chrono::steady_clock::now();
    const RaColoredFit cf =
        fit_ra_colors(read_ra_table(file), base, out.held, out.color, out.objective, out.spectrum);
    const RaMeasurements& t = cf.rows; // a coloured table: the rows of the colour fitted
    const RaNodeFit& nf = cf.fit;
    const RaMrmFit mf = fit_ra_mrm(t, out.objective);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!out.mtlx.empty())
        write_mtlx(out.mtlx, {{out.name, nf.params}}, ra_fit_document_comment(t, nf, mf));
    if (!out.plot.empty()) {
        plot::Text text("retroprism fit");
        plot::write_png(plot::ra_fit_figure(t, nf, mf, text), out.plot);
    }
    if (out.json) {
        std::printf("%s\n", ra_fit_json(cf, mf).dump().c_str());
        return 0;
    }
    std::printf("table: %s (%zu rows), R_A [cd lx^-1 m^-2]\n", t.file.c_str(), t.entries.size());
    for (const std::string& c : t.comments)
        std::printf("  # %s\n", c.c_str());
    // In RaObjective's order.
    const char* objectives[] = {"RMS of ln(model / measured)",
                                "largest square of ln(model / measured)",
                                "largest |model - measured| / measured"};
    std::printf("objective: %s over the rows, each row alike; rows without a rotation angle: the "
                "mean over rotations 0 and 90 deg; the node's R_A %s\n\n",
                objectives[int(out.objective)],
                out.spectrum == RaSpectrum::Photopic
                    ? "photopic (illuminant A x V(lambda) over 15 wavelengths, 410-690 nm)"
                    : "the luminance of its channels");
    std::printf("%-20s %-26s %-26s\n", "", "node (prismatic retroreflector)",
                "mrm (retroreflective GGX + Lambert)");
    std::printf("%-20s %-26s %-26s\n", "fitted inputs", "from the parameter table",
                "roughness, ior, specular");
    for (const std::string& n : nf.fitted) {
        std::string m = "-";
        if (n == "roughness") m = plot::fmt("%.6g (GGX)", mf.model.roughness);
        if (n == "ior") m = plot::fmt("%.6g", mf.model.ior);
        std::printf("%-20s %-26s %-26s\n", n.c_str(), ra_fit_input_text(nf.params, n).c_str(),
                    m.c_str());
    }
    std::printf("%-20s %-26s %-26s\n\n", "specular", "-",
                plot::fmt("%.6g", mf.model.specular).c_str());
    print_ra_comparison(t, {{"node", nf.report.model}, {"mrm", mf.report.model}}, stdout);
    print_ra_color_fits(cf.colors, stdout);
    std::printf("\nruntime %.1f s (%d + %d evaluations of the table)\n", seconds, nf.evaluations,
                mf.evaluations);
    if (!out.mtlx.empty())
        std::printf("wrote %s (material \"%s\")\n", out.mtlx.c_str(), out.name.c_str());
    if (!out.plot.empty()) std::printf("wrote %s\n", out.plot.c_str());
    return 0;
}

void require_folder(const std::string& option, const std::string& path) {
    if (path.empty()) return;
    const fs::path dir = fs::path(path).parent_path();
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw InputError(option + " " + path + ": no folder " + dir.string());
}

} // namespace

int cmd_fit(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism fit: fits the node (roughness, ior, specular, retro_color, diffuse_color, "
             "prism_reflection, cant_angle, dihedral_error, dihedral_spread) and the "
             "MaterialX-style retroreflective GGX baseline to measured BRDF x cos(theta_v) in the "
             "ALTA text format (#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI), weighting peaks and floor "
             "alike in log space, with the instrument's angular resolution as a Gaussian blur. "
             "With --ra, fits the inputs the parameter table declares fittable, and the baseline, "
             "to a table of R_A (CSV: observation_deg, entrance_deg, ra, optional rotation_deg, "
             "presentation_deg and color) in log space; a coloured table's geometry on its white "
             "rows, each colour's retro_color on its rows, with the hue of --material")
        .usage("retroprism fit DATA.dat [--json] [--plot OUT.png] [--resolution FWHM_DEG] [--ior "
               "ETA] [--paper-geometry] [--param-out NAME]\n       retroprism fit --ra TABLE.csv "
               "[--json] [--plot OUT.png] [--mtlx OUT.mtlx [--name NAME]] [--material BASE.json] "
               "[--hold NAME,...] [--objective rms|max|relative] [--photopic] [--color NAME]\n"
               "       retroprism fit --ra TABLE.csv --baseline-only [--json]");
    std::string file;
    ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> a) { file = a[0]; });
    ap.arg("--json")
        .help("print only {\"params\", \"rel_rms\", \"log_rms\", \"mrm\": {...}} as JSON (--ra: "
              "{\"table\", \"fitted\", \"params\", \"log_rms\", \"max_error\", \"entries\", "
              "\"mrm\"})")
        .store_true();
    ap.arg("--plot FILE")
        .help("write in-plane slices (--ra: R_A against observation angle), measured vs fitted, "
              "as a PNG");
    ap.arg("--resolution DEG")
        .help("FWHM of the instrument's Gaussian angular blur in degrees, 0 for none (default "
              "1.07, the sampling of the CEA measurements)")
        .defaultval("1.07");
    ap.arg("--ior ETA")
        .help("fix the ior of both models (e.g. 1.49 for acrylic) instead of fitting it");
    ap.arg("--paper-geometry")
        .help("hold the node's cant_angle, dihedral_error and dihedral_spread at 0 (the paper's "
              "cube) instead of fitting them")
        .store_true();
    ap.arg("--param-out NAME")
        .help("the output of an ALTA file without #PARAM_OUT: INV_STERADIAN_COSINE_FACTOR "
              "(assumed, with a warning, when not given) or INV_STERADIAN");
    ap.arg("--ra TABLE").help("fit a table of R_A (CSV) instead of ALTA data");
    ap.arg("--mtlx FILE").help("--ra: write the fitted node as a MaterialX document");
    ap.arg("--name NAME").help("--ra: the material's name in --mtlx (default: its file stem)");
    ap.arg("--material FILE")
        .help("--ra: the inputs not fitted, as a JSON material (default: the node's defaults)");
    ap.arg("--hold NAMES")
        .help("--ra: fittable inputs (comma-separated) kept at the base material's value instead "
              "of fitted");
    ap.arg("--objective NAME")
        .help("--ra: rms (default; the mean square of ln(model / measured)), max (its largest "
              "square) or relative (the largest |model - measured| / measured)");
    ap.arg("--color NAME")
        .help("--ra, a table with a color column: the colour of the material written and "
              "reported (default: white, or the table's first colour)");
    ap.arg("--photopic")
        .help("--ra: the node's R_A as a photometer under illuminant A sees it (15 wavelengths "
              "410-690 nm weighted by illuminant A x V(lambda)) instead of the luminance of its "
              "channels; the base material's wavelength is replaced")
        .store_true();
    ap.arg("--baseline-only")
        .help("--ra: fit only the MaterialX-style GGX baseline (with --json: {\"table\", "
              "\"mrm\": {\"params\", \"log_rms\", \"max_error\", \"entries\"}})")
        .store_true();
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    const std::string plotPath = ap["plot"].get<std::string>();
    require_folder("--plot", plotPath);

    const std::string raFile = ap["ra"].get<std::string>();
    if (!raFile.empty()) {
        if (!file.empty())
            throw InputError("fit: give either DATA.dat or --ra TABLE.csv, not both");
        for (const char* option : {"ior", "param-out"})
            if (!ap[option].get<std::string>().empty())
                throw InputError(std::string("--") + option + " goes with ALTA data, not --ra");
        if (ap["paper-geometry"].get<int>())
            throw InputError("--paper-geometry goes with ALTA data, not --ra");
        RaFitOutputs out;
        out.plot = plotPath;
        out.json = ap["json"].get<int>() != 0;
        out.baselineOnly = ap["baseline-only"].get<int>() != 0;
        const std::string objective = ap["objective"].get<std::string>();
        if (!objective.empty()) out.objective = ra_objective(objective);
        if (out.baselineOnly)
            for (const char* option : {"plot", "mtlx", "name", "material", "hold", "color"})
                if (!ap[option].get<std::string>().empty())
                    throw InputError(std::string("--") + option +
                                     " goes with the node's fit, not --baseline-only");
        if (ap["photopic"].get<int>()) {
            if (out.baselineOnly)
                throw InputError("--photopic goes with the node's fit, not --baseline-only (the "
                                 "baseline does not depend on the wavelength)");
            out.spectrum = RaSpectrum::Photopic;
        }
        for (std::stringstream holds(ap["hold"].get<std::string>()); holds.good();) {
            std::string name;
            std::getline(holds, name, ',');
            if (!name.empty()) out.held.push_back(name);
        }
        out.mtlx = ap["mtlx"].get<std::string>();
        out.name = ap["name"].get<std::string>();
        out.color = ap["color"].get<std::string>();
        require_folder("--mtlx", out.mtlx);
        if (out.name.empty()) out.name = fs::path(out.mtlx).stem().string();
        if (!out.mtlx.empty()) mtlx_document({{out.name, Params()}}, {}); // checks the name
        const std::string base = ap["material"].get<std::string>();
        return fit_ra_table(raFile,
                            base.empty() ? Params() : params_from_json(read_json(base), base), out);
    }
    for (const char* option : {"mtlx", "name", "material", "hold", "color", "objective"})
        if (!ap[option].get<std::string>().empty())
            throw InputError(std::string("--") + option + " goes with --ra TABLE.csv");
    for (const char* flag : {"baseline-only", "photopic"})
        if (ap[flag].get<int>())
            throw InputError(std::string("--") + flag + " goes with --ra TABLE.csv");
    if (file.empty())
        throw InputError("fit: give a data file in the ALTA text format, or --ra TABLE.csv");

    const auto t0 = std::chrono::steady_clock::now();
    FitOptions o;
    o.resolution_fwhm_deg =
        parse_number_in(ap["resolution"].get<std::string>(), "--resolution", 0.0, 10.0);
    if (!ap["ior"].get<std::string>().empty())
        o.fixed_ior = parse_number_in(ap["ior"].get<std::string>(), "--ior", 1.01, 3.0);
    o.paper_geometry = ap["paper-geometry"].get<int>() != 0;
    const AltaData alta = read_alta(file, ap["param-out"].get<std::string>());
    if (!alta.warning.empty())
        std::fprintf(stderr, "retroprism fit: warning: %s\n", alta.warning.c_str());
    const FitData d = fit_data(alta);
    const NodeFit nf = fit_node(d, o);
    const MrmFit mf = fit_mrm(d, o);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    if (!plotPath.empty()) {
        plot::Text text("retroprism fit");
        plot::write_png(
            plot::fit_figure(fs::path(file).filename().string(), slices(d, nf, mf, o), text),
            plotPath);
    }
    if (ap["json"].get<int>()) {
        std::printf("%s\n", fit_json(nf, mf).dump().c_str());
    } else {
        print_report(d, alta, o, nf, mf, seconds);
        if (!plotPath.empty()) std::printf("wrote %s\n", plotPath.c_str());
    }
    return 0;
}

} // namespace retroprism
