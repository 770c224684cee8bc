// cmd_simulate.cpp: `retroprism simulate`, the microgeometry simulator (sim/microgeometry.h,
// MODEL.md section 6) as a command: the tabulated BRDF per lobe with standard errors for a set of
// incident directions, as EXR and JSON (sim/brdf_table.h, report/brdf_table_files.h); and
// `retroprism simulate --study`, the accuracy study (sim/study.h), which regenerates
// docs/accuracy.md from its template, its plots and results.csv (report/accuracy_report.h); and
// `retroprism simulate --wave` (cmd_simulate_wave.cpp).
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/argparse.h>

#include "accuracy_plots.h"
#include "accuracy_report.h"
#include "brdf_table_files.h"
#include "commands.h"
#include "text_file.h"
#include "parse.h"
#include "paths.h"
#include "progress.h"
#include "query.h"
#include "study_results.h"
#include "template.h"

namespace fs = std::filesystem;

namespace retroprism {

namespace {

// The folder of an output prefix (of option `option`) exists and is writable, before any work is
// done.
void check_prefix(const std::string& prefix, const std::string& option = "--out") {
    if (prefix.empty()) throw InputError(option + ": empty prefix");
    fs::path dir = fs::path(prefix).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw InputError(option + " " + prefix + ": folder " + dir.string() + " does not exist");
    const fs::path probe = dir / (".retroprism-write-test" + std::to_string(getpid()));
    {
        std::ofstream f(probe);
        if (!f || !(f << "x") || (f.close(), !f)) {
            fs::remove(probe, ec);
            throw InputError(option + " " + prefix + ": folder " + dir.string() +
                             " is not writable");
        }
    }
    fs::remove(probe, ec);
}

// A progress bar on the terminal per simulation, from its label.
sim::RunOptions::Progress progress_bar(const std::string& label) {
    auto bar = std::make_shared<ProgressBar>(label);
    return [bar](std::uint64_t done, std::uint64_t total) { (*bar)(done, total); };
}

std::string pct(double v) {
    if (!std::isfinite(v)) return "n/a";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%+.1f%%", 100 * v);
    return buf;
}

int threads_option(const std::string& text) {
    return text == "0" ? 0 : int(parse_count(text, "--threads", 1, 256));
}

void print_table(const sim::BrdfTable& table, std::uint64_t rays, const std::string& exrPath) {
    const sim::Run& r0 = table.runs[0];
    const sim::Tally& t = r0.tally;
    const double n = double(rays);
    std::printf("theta_i %5.1f: surface %.5f  retro %.5f  diffuse %.5f  absorbed %.5f  "
                "trapped %llu  (channel 0, %llu rays, %.3g rays/s on %d threads) -> %s\n",
                table.theta_i_deg, double(t.fates[sim::kFateSurface]) / n,
                double(t.fates[sim::kFateRetro]) / n, double(t.fates[sim::kFateDiffuse]) / n,
                double(t.fates[sim::kFateAbsorbedSubstrate] + t.fates[sim::kFateAbsorbedFaces]) / n,
                (unsigned long long)t.fates[sim::kFateTrapped], (unsigned long long)rays,
                r0.rays_per_second(), r0.threads, exrPath.c_str());
}

void print_config(const sim::ConfigResult& r) {
    std::printf("%-40s sim: retro %.5f (fit %.4f %.4f) diffuse(n) %.4f | widths %s %s | energy "
                "%s %s %s %s  (%.1f s)\n",
                sim::config_label(r.c).c_str(), r.sim.energy.value, r.sim.fit.ax, r.sim.fit.ay,
                r.sim.diffuseNormal.value, pct(sim::width_err(r, 0, true)).c_str(),
                pct(sim::width_err(r, 1, true)).c_str(), pct(sim::energy_err(r, 0)).c_str(),
                pct(sim::energy_err(r, 1)).c_str(), pct(sim::energy_err(r, 2)).c_str(),
                pct(sim::energy_err(r, 3)).c_str(), r.sim.seconds);
    std::fflush(stdout);
}

// The study's options on the command line (--merge takes them from the shards, --load from the
// archive but --quick).
sim::StudyOptions study_options(OIIO::ArgParse& ap) {
    sim::StudyOptions so;
    so.rays = parse_count(ap["rays"].get<std::string>(), "--rays", 1000, 1e12);
    so.recipRays = parse_count(ap["recip_rays"].get<std::string>(), "--recip-rays", 1000, 1e12);
    so.diffuseRays =
        parse_count(ap["diffuse_rays"].get<std::string>(), "--diffuse-rays", 1000, 1e12);
    so.seed = parse_count(ap["seed"].get<std::string>(), "--seed", 0, 9.0e15);
    so.threads = threads_option(ap["threads"].get<std::string>());
    so.quick = ap["quick"].get<int>() != 0;
    return so;
}

// `simulate --study --shard K/N --save FILE`: the shard's units, saved.
int study_shard(const sim::StudyOptions& so, const std::string& text, const std::string& save) {
    if (save.empty())
        throw InputError("--shard " + text + ": --save FILE is required (the shard's results)");
    const std::vector<sim::StudyUnit> units = sim::study_units(so);
    const sim::ShardSpec spec = sim::parse_shard(text, "--shard", units.size());
    check_prefix(save, "--save");
    const sim::StudyShard shard = sim::run_study_shard(so, spec, {progress_bar, print_config});
    sim::save_study_shard(save, shard);
    double rays = 0;
    for (const sim::UnitResult& u : shard.units)
        rays += double(u.rays);
    std::printf("wrote shard %s (%zu of the study's %zu units, %.4g rays) to %s in %.1f min; "
                "merge every shard with simulate --study --merge\n",
                text.c_str(), shard.units.size(), units.size(), rays, save.c_str(),
                shard.elapsed / 60);
    return 0;
}

// The document from its template, its plots and results.csv into `plotDir` next to it.
void write_study(const sim::StudyResults& study, const fs::path& doc, const fs::path& plotDir) {
    const std::string templatePath = data_path("docs/accuracy.md.in");
    const std::string tmpl = read_text_file(templatePath);
    sim::write_results_csv((plotDir / "results.csv").string(), study.results);
    const std::string md = report::accuracy_report(study, tmpl, templatePath, doc.string(),
                                                   plotDir.filename().string());
    const fs::path tmpDoc = doc.string() + ".tmp" + std::to_string(getpid());
    {
        std::ofstream f(tmpDoc);
        f << md;
        if (!f) throw InputError(doc.string() + ": cannot write");
    }
    std::error_code ec;
    fs::rename(tmpDoc, doc, ec);
    if (ec) throw InputError(doc.string() + ": cannot write (" + ec.message() + ")");
    report::write_accuracy_plots(study, plotDir.string());
}

// `simulate --study`: the options, the runs (or a shard, --merge, --load), results.csv, the
// document, the plots.
int study_command(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism simulate --study: the accuracy study: every analytic variant "
             "(retro_lobe isotropic|anisotropic x reciprocal false|true) against the "
             "microgeometry simulator for theta_i in {0, 20, 40, 60, 75, 85} deg, roughness in "
             "{0.005, 0.02, 0.1, 0.3}, ior in {1.49, 1.586}, prism_reflection tir and metallized "
             "(diffuse_color 0.9, era_mode averaged). Writes FILE.md (default docs/accuracy.md) "
             "from the template docs/accuracy.md.in, its plots and results.csv into the folder "
             "`accuracy` next to it. In shards (docs/simulate.md): each of N processes runs "
             "--shard K/N --save PART_K, then --merge PART_1 ... PART_N writes what one process "
             "would have, the same results bit for bit.")
        .usage("retroprism simulate --study [--rays N] [--diffuse-rays N] [--recip-rays N] "
               "[--seed S] [--threads T] [--doc FILE.md] [--quick] [--save FILE] [--load FILE] "
               "[--shard K/N --save PART] [--merge PART...]");
    ap.arg("--study").help("run the accuracy study").store_true();
    ap.arg("--rays N").help("rays per configuration (default 4000000)").defaultval("4000000");
    ap.arg("--diffuse-rays N")
        .dest("diffuse_rays")
        .help("rays per configuration of the diffuse-model runs with the paper's way up "
              "(default 1000000)")
        .defaultval("1000000");
    ap.arg("--recip-rays N")
        .dest("recip_rays")
        .help("rays per cone of incidence of the reciprocity runs (default 400000)")
        .defaultval("400000");
    ap.arg("--seed S")
        .help("base seed (default 2018; configuration k uses S + k)")
        .defaultval("2018");
    ap.arg("--threads T").help("threads (default: all cores)").defaultval("0");
    ap.arg("--doc FILE.md")
        .help("the document (default docs/accuracy.md)")
        .defaultval("docs/accuracy.md");
    ap.arg("--quick")
        .help("a small subset (theta_i 20 and 60, roughness 0.1, ior 1.49, tir): a smoke test of "
              "the command, not the study")
        .store_true();
    ap.arg("--save FILE").help("also write the results as numbers to FILE");
    ap.arg("--load FILE")
        .help("redo the document and plots from FILE (written by --save with the "
              "same --quick) instead of simulating");
    ap.arg("--shard K/N")
        .help("run only shard K of N (1 <= K <= N <= the study's work units) and write its "
              "partial results to --save PART; no document");
    ap.arg("--merge PART...")
        .help("write the document, plots, results.csv (and --save) from the partial results of "
              "all N shards of a study (its options are theirs) instead of simulating");
    int status = 0;
    std::vector<std::string> parts;
    bool merge = false;
    if (!parse_args_with_values(ap, argc, argv, "--merge", parts, merge, status)) return status;
    if (!merge && !parts.empty())
        throw InputError("simulate --study: unexpected argument " + parts[0] +
                         " (--merge PART... takes the shards' files)");
    if (merge && parts.empty()) throw InputError("--merge: expected the shards' files");
    const sim::StudyOptions so = study_options(ap);
    const std::string load = ap["load"].get<std::string>(), save = ap["save"].get<std::string>();
    const std::string shard = ap["shard"].get<std::string>();
    if (int(merge) + int(!load.empty()) + int(!shard.empty()) > 1)
        throw InputError("simulate --study: --shard, --merge and --load exclude each other");
    if (!shard.empty()) return study_shard(so, shard, save);

    const fs::path doc = ap["doc"].get<std::string>();
    if (doc.extension() != ".md")
        throw InputError("--doc " + doc.string() + ": expected a .md file name");
    // The results read (--merge, --load) before any folder is made, or simulated after.
    std::optional<sim::StudyResults> read;
    if (merge) {
        std::vector<sim::StudyShard> shards;
        for (const std::string& part : parts)
            shards.push_back(sim::load_study_shard(part));
        read = sim::merge_study_shards(shards);
    } else if (!load.empty()) {
        read = sim::load_study(load, so.quick);
    }
    const fs::path plotDir =
        (doc.parent_path().empty() ? fs::path(".") : doc.parent_path()) / "accuracy";
    std::error_code ec;
    fs::create_directories(plotDir, ec);
    if (ec || !fs::is_directory(plotDir))
        throw InputError("--doc " + doc.string() + ": cannot create " + plotDir.string());
    check_prefix((plotDir / "probe").string());
    const sim::StudyResults study =
        read ? std::move(*read) : sim::run_study(so, {progress_bar, print_config});
    if (!save.empty()) sim::save_study(save, study);
    write_study(study, doc, plotDir);
    std::printf("wrote %s, %zu plots and %s in %.1f min (%.3g rays/s on %d threads)\n",
                doc.string().c_str(), report::accuracy_plot_names(study.grid).size(),
                (plotDir / "results.csv").string().c_str(), study.elapsed / 60,
                study.simRays / study.simSeconds, study.threadsUsed);
    return 0;
}

} // namespace

int cmd_simulate(int argc, const char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--study") == 0) return study_command(argc, argv);
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--wave") == 0) return simulate_wave_command(argc, argv);
    OIIO::ArgParse ap;
    ap.intro("retroprism simulate: the microgeometry Monte Carlo (MODEL.md section 6): the "
             "tabulated BRDF per lobe with standard errors for each incident direction, as "
             "PREFIX_thetaDEG.exr (one part per grid) and PREFIX.json. `retroprism simulate "
             "--study --help` describes the accuracy study, `retroprism simulate --wave --help` "
             "the physical-optics R_A.")
        .usage("retroprism simulate [--material FILE.json] --theta-i DEG... [--phi-i DEG] "
               "[--rays N] [--seed S] [--threads T] [--way-up prisms|direct] [--out PREFIX]");
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
    std::vector<double> angles;
    int status = 0;
    if (!parse_args_with_theta_i(ap, argc, argv, angles, status)) return status;
    Params p;
    const std::string file = ap["material"].get<std::string>();
    if (!file.empty()) p = params_from_json(read_json(file), file);
    const double phi = parse_number(ap["phi_i"].get<std::string>(), "--phi-i");
    sim::TableOptions o;
    o.rays = parse_count(ap["rays"].get<std::string>(), "--rays", 1, 1e12);
    o.seed = parse_count(ap["seed"].get<std::string>(), "--seed", 0, 9.0e15);
    o.threads = threads_option(ap["threads"].get<std::string>());
    const std::string way = ap["way_up"].get<std::string>();
    if (way != "prisms" && way != "direct")
        throw InputError("--way-up " + way + ": expected prisms or direct");
    o.way_up_through_prisms = way == "prisms";
    o.progress = progress_bar;
    const std::string prefix = ap["out"].get<std::string>();
    check_prefix(prefix);

    nlohmann::json doc = report::simulation_json(p, o);
    double totalRays = 0, totalSeconds = 0;
    int usedThreads = 1;
    for (double thetaI : angles) {
        const sim::BrdfTable table = sim::tabulate_brdf(p, thetaI, phi, o);
        for (int c = 0; c < 3; ++c)
            if (table.run_of[c] == c) {
                totalRays += double(o.rays);
                totalSeconds += table.runs[size_t(c)].seconds;
                usedThreads = table.runs[size_t(c)].threads;
            }
        char name[64];
        std::snprintf(name, sizeof name, "_theta%g.exr", thetaI);
        const std::string exrPath = prefix + name;
        report::write_table_exr(
            exrPath, table,
            {{"theta_i_deg", thetaI}, {"phi_i_deg", phi}, {"rays", o.rays}, {"seed", o.seed}});
        doc["incidences"].push_back(report::incidence_json(table, o.rays, exrPath));
        print_table(table, o.rays, exrPath);
    }
    const std::string jsonPath = prefix + ".json";
    report::write_json_file(jsonPath, doc);
    std::printf("wrote %s; %.4g rays/s on %d threads overall\n", jsonPath.c_str(),
                totalSeconds > 0 ? totalRays / totalSeconds : 0.0, usedThreads);
    return 0;
}

} // namespace retroprism
