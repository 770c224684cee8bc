// retroprism bench: the speed/accuracy trade table, from the Google Benchmark benchmarks of
// bench/benchmarks.cpp run in this process: ns per evaluation and per sample + pdf of each
// fidelity tier and lobe set, the ratio to the MaterialX-style retroreflective GGX, and each
// row's relative L1 error against the double reference; a cost-error plot with the Pareto front.
#include <benchmark/benchmark.h>

#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <nlohmann/json.hpp>

#include "benchmarks.h"
#include "check.h"
#include "commands.h"
#include "parse.h"
#include "cost_error_plot.h"
#include "embedded_files.h"
#include "gl_runner.h"
#include "glsl_gen.h"
#include "paths.h"
#include "plot.h"
#include "query.h"
#include "study_results.h"

namespace retroprism {

namespace {

// Collects each benchmark's CPU time per iteration (ns): the median of its repetitions when
// there are several, else its one run.
class Collector : public benchmark::BenchmarkReporter {
  public:
    std::map<std::string, double> ns;
    bool ReportContext(const Context&) override { return true; }
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& r : runs) {
            if (r.error_occurred) continue;
            const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
            const bool single = r.run_type == Run::RT_Iteration && r.repetitions <= 1;
            if (!median && !single) continue;
            ns[r.run_name.str()] = r.GetAdjustedCPUTime() *
                                   benchmark::GetTimeUnitMultiplier(benchmark::kNanosecond) /
                                   benchmark::GetTimeUnitMultiplier(r.time_unit);
        }
    }
};

std::string fmt_num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f", v);
    return b;
}

std::string fmt_err(double e) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g", e);
    return b;
}

struct Result {
    const bench::Row* row;
    double nsEval = 0, nsEvalPdf = -1, nsSample = -1, ratio = 0;
    // Against the double reference over the standard direction pairs (negative: none).
    double error = -1;     // relative L1: sum |f - f_ref| / sum |f_ref|
    double rms = -1;       // relative RMS: sqrt(sum (f - f_ref)^2 / sum f_ref^2)
    double worst = -1;     // worst |f - f_ref| / f_ref over values >= 1e-3 of their lobe's peak
    double retroPeak = -1; // worst relative error of the retro lobe at wo = wi
    // Against the microgeometry simulator (docs/accuracy/results.csv), over the study's
    // configurations of the row's prisms: retro energy and retro peak, RMS and worst of the
    // relative error (negative: none).
    double simEnergyRms = -1, simEnergyWorst = -1, simPeakRms = -1, simPeakWorst = -1;
    int simConfigs = 0;
};

// The row's errors against the double reference over the standard direction pairs of
// `retroprism check` for the row's material (its normal is +z: the pairs are local).
void reference_errors(const bench::Row& row, Result& res) {
    const std::vector<DirectionPair> pairs = standard_pairs(row.material);
    const bench::LocalEval f = row.make_eval(row.material);
    const PrismaticRetroreflector<double> ref(row.reference);
    std::vector<std::array<glm::dvec3, 3>> got(pairs.size()), want(pairs.size());
    double peak[3] = {0, 0, 0};
    for (size_t i = 0; i < pairs.size(); ++i) {
        const glm::dvec3 wi(pairs[i].wi[0], pairs[i].wi[1], pairs[i].wi[2]);
        const glm::dvec3 wo(pairs[i].wo[0], pairs[i].wo[1], pairs[i].wo[2]);
        f(wi, wo, got[i].data());
        const auto e = ref.eval(wi, wo);
        want[i] = {e.f.surface, e.f.retro, e.f.diffuse};
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c)
                peak[k] = std::max(peak[k], std::abs(want[i][size_t(k)][c]));
    }
    double l1 = 0, l1ref = 0, l2 = 0, l2ref = 0, worst = 0, retroPeak = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            if (!(row.mask & (1 << k))) continue;
            for (int c = 0; c < 3; ++c) {
                const double a = got[i][size_t(k)][c], b = want[i][size_t(k)][c];
                l1 += std::abs(a - b);
                l1ref += std::abs(b);
                l2 += (a - b) * (a - b);
                l2ref += b * b;
                if (std::abs(b) >= 1e-3 * peak[k] && b != 0)
                    worst = std::max(worst, std::abs(a - b) / std::abs(b));
            }
        }
        if ((row.mask & 2) && pairs[i].wi == pairs[i].wo && want[i][1].x > 0)
            retroPeak = std::max(retroPeak, std::abs(got[i][1].x / want[i][1].x - 1.0));
    }
    res.error = l1ref > 0 ? l1 / l1ref : 0;
    res.rms = l2ref > 0 ? std::sqrt(l2 / l2ref) : 0;
    res.worst = worst;
    if (row.mask & 2) res.retroPeak = retroPeak;
}

// One configuration of the simulator's accuracy study.
struct SimConfig {
    double thetaDeg, roughness, ior;
    int prism;
    double simPeak, simEnergy; // simulated: retro peak (1/sr, cell average), retro energy
    double modelPeak;          // the double reference's peak averaged over the same cells
};

// The study's configurations from its results file (sim/study_results.h).
std::vector<SimConfig> read_study(const std::string& path) {
    std::vector<SimConfig> out;
    for (const sim::ConfigResult& r : sim::read_results_csv(path))
        out.push_back({r.c.theta, r.c.alpha, r.c.eta, r.c.prism, r.sim.peak.value,
                       r.sim.energy.value, r.v[0].peak});
    return out;
}

// The row's retro lobe against the simulator, over the study's configurations with the row's
// prisms (the study's material: kd 0.9, isotropic lobe, the paper's form; phi_i = 0). Energy:
// the row's retro albedo, integrated over the double reference's retro sampling map (64 x 64
// midpoints, weights f cos / pdf), against the simulated retro fraction. Peak: the study's
// cell-averaged reference peak scaled by the row's peak over the reference's at wo = wi.
void simulator_errors(const bench::Row& row, const std::vector<SimConfig>& study, Result& res) {
    if (!(row.mask & 2)) return;
    double e2 = 0, p2 = 0, eWorst = 0, pWorst = 0;
    int n = 0;
    for (const SimConfig& c : study) {
        if (c.prism != row.material.prism_reflection) continue;
        Params p = row.material, q = row.reference;
        for (Params* x : {&p, &q}) {
            x->roughness = c.roughness;
            x->ior = c.ior;
            x->diffuse_color = {0.9, 0.9, 0.9};
        }
        const bench::LocalEval f = row.make_eval(p);
        const PrismaticRetroreflector<double> ref(q);
        const double t = c.thetaDeg * M_PI / 180.0;
        const glm::dvec3 wi(std::sin(t), 0.0, std::cos(t));
        glm::dvec3 got[3];
        f(wi, wi, got);
        const double refPeak = ref.eval(wi, wi).f.retro.x;
        const double peakErr = refPeak > 0 ? c.modelPeak * (got[1].x / refPeak) / c.simPeak - 1 : 0;
        using Core = core<double>;
        Core::incident s;
        Core::setup(ref.core_material(), wi, s);
        const int g = 64;
        double energy = 0;
        for (int a = 0; a < g; ++a)
            for (int b = 0; b < g; ++b) {
                const glm::dvec3 wo = Core::lobe_sample(
                    ref.core_material(), s, wi, f64::RP_LOBE_RETRO, (a + 0.5) / g, (b + 0.5) / g);
                if (!(wo.z >= f64::RP_MIN_COS)) continue;
                const double pdf =
                    Core::lobe_pdf(ref.core_material(), s, wi, wo, f64::RP_LOBE_RETRO);
                if (!(pdf > 0)) continue;
                f(wi, wo, got);
                energy += got[1].x * wo.z / pdf;
            }
        energy /= double(g) * g;
        const double energyErr = energy / c.simEnergy - 1;
        e2 += energyErr * energyErr;
        p2 += peakErr * peakErr;
        if (std::abs(energyErr) > std::abs(eWorst)) eWorst = energyErr;
        if (std::abs(peakErr) > std::abs(pWorst)) pWorst = peakErr;
        ++n;
    }
    if (n == 0) return;
    res.simConfigs = n;
    res.simEnergyRms = std::sqrt(e2 / n);
    res.simEnergyWorst = eWorst;
    res.simPeakRms = std::sqrt(p2 / n);
    res.simPeakWorst = pWorst;
}

// The GLSL variants' relative cost: SPIR-V instructions after optimisation, and evaluations per
// second on this machine's OpenGL (llvmpipe without a GPU), excluding shader compilation.
void glsl_costs(bool json) {
    const int n = 100000;
    std::vector<std::array<Vec3d, 2>> pairs;
    for (int i = 0; i < n; ++i) {
        const double t = 0.05 + 1.4 * double((i * 7919LL) % n) / n;
        const double p = 6.283 * double((i * 104729LL) % n) / n;
        const Vec3d wi = {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
        pairs.push_back(
            {wi, {-wi[0] * 0.9, -wi[1] * 0.9, std::sqrt(1.0 - 0.81 * (1.0 - wi[2] * wi[2]))}});
    }
    nlohmann::json rows = nlohmann::json::array();
    if (!json)
        std::printf("\n%-52s %14s %16s\n", "GLSL variant", "SPIR-V instr.", "llvmpipe eval/s");
    for (const glsl::Variant& v : glsl::standard_variants()) {
        const std::string lib = embedded_variant(v.name);
        const long instr = glsl::spirv_instructions(lib, v.name);
        gl::Runner runner(lib);
        Params p;
        if (v.era_mode >= 0) p.era_mode = v.era_mode;
        if (v.prism_reflection >= 0) p.prism_reflection = v.prism_reflection;
        if (v.fidelity >= 0) p.fidelity = v.fidelity;
        runner.evaluate(p, {pairs.begin(), pairs.begin() + 64}); // warm up
        const auto t0 = std::chrono::steady_clock::now();
        runner.evaluate(p, pairs);
        const double secs =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double rate = n / secs;
        if (json)
            rows.push_back({{"variant", v.name},
                            {"spirv_instructions", instr},
                            {"llvmpipe_evals_per_second", rate}});
        else
            std::printf("%-52s %14ld %16.3g\n", v.name.c_str(), instr, rate);
    }
    if (json) std::printf("%s\n", nlohmann::json{{"glsl", rows}}.dump(2).c_str());
}

void write_plot(const std::vector<Result>& results, const std::string& path) {
    std::vector<plot::CostErrorPoint> points;
    double baseline = 0;
    for (const Result& r : results) {
        points.push_back({r.row->name, r.nsEval, r.error});
        if (r.row->name == "mrm_ggx") baseline = r.nsEval;
    }
    const OIIO::ImageBuf img = plot::cost_error_figure(points, baseline);
    if (!img.write(path))
        throw InputError(path + ": cannot write the plot (" + img.geterror() + ")");
}

} // namespace

int cmd_bench(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism bench: the speed/accuracy trade table (Google Benchmark, this machine)")
        .usage("retroprism bench [--json] [--plot OUT.png] [--min-time SECONDS] [--repetitions N] "
               "[--glsl]");
    ap.arg("--json").help("print the rows as JSON").store_true();
    ap.arg("--glsl")
        .help("also the GLSL variants' SPIR-V size and llvmpipe throughput")
        .store_true();
    ap.arg("--plot OUT.png").help("write the cost-error plot with the Pareto front");
    ap.arg("--min-time SECONDS")
        .dest("min_time")
        .help("minimum time per benchmark (default 0.2)")
        .defaultval("0.2");
    ap.arg("--repetitions N")
        .dest("repetitions")
        .help("runs of each benchmark, interleaved at random; the table shows their median "
              "(default 3, in [1, 20])")
        .defaultval("3");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    const std::string minTime = ap["min_time"].get<std::string>();
    const std::optional<double> mt = try_parse_number(minTime);
    if (!mt || !(*mt > 0 && *mt <= 60))
        throw InputError("--min-time " + minTime + ": expected seconds in (0, 60]");
    const auto reps = parse_count(ap["repetitions"].get<std::string>(), "--repetitions", 1, 20);

    const std::vector<bench::Row>& rows = bench::rows();
    std::string flag = "--benchmark_min_time=" + minTime;
    // Repetitions interleaved at random over all benchmarks, so that a slow spell of the
    // machine spreads over the rows instead of landing on one.
    std::string repFlag = "--benchmark_repetitions=" + std::to_string(reps);
    std::string interleave = "--benchmark_enable_random_interleaving=true";
    std::vector<char*> bargs = {const_cast<char*>("retroprism"), flag.data(), repFlag.data(),
                                interleave.data()};
    int bargc = int(bargs.size());
    benchmark::Initialize(&bargc, bargs.data());
    Collector collector;
    benchmark::RunSpecifiedBenchmarks(&collector);

    const std::vector<SimConfig> study = read_study(data_path("docs/accuracy/results.csv"));
    std::vector<Result> results;
    double mrm = 0;
    for (const bench::Row& r : rows) {
        Result res;
        res.row = &r;
        res.nsEval = collector.ns["eval/" + r.name] / bench::kPairs;
        if (r.has_sample) {
            res.nsEvalPdf = collector.ns["eval_pdf/" + r.name] / bench::kPairs;
            res.nsSample = collector.ns["sample_pdf/" + r.name] / bench::kPairs;
        }
        if (!r.baseline) {
            reference_errors(r, res);
            simulator_errors(r, study, res);
        }
        if (r.name == "mrm_ggx") mrm = res.nsEval;
        results.push_back(res);
    }
    for (Result& r : results)
        r.ratio = mrm > 0 ? r.nsEval / mrm : 0;

    auto opt = [](double v) { return v >= 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
    if (ap["json"].get<int>()) {
        nlohmann::json out = {{"rows", nlohmann::json::array()}};
        for (const Result& r : results)
            out["rows"].push_back({{"name", r.row->name},
                                   {"tier", r.row->tier},
                                   {"lobes", r.row->lobes},
                                   {"config", r.row->config},
                                   {"ns_per_eval", r.nsEval},
                                   {"ns_per_eval_pdf", opt(r.nsEvalPdf)},
                                   {"ns_per_sample_pdf", opt(r.nsSample)},
                                   {"ratio_to_mrm", r.ratio},
                                   {"rel_l1_error", opt(r.error)},
                                   {"rel_rms_error", opt(r.rms)},
                                   {"worst_rel_error", opt(r.worst)},
                                   {"retro_peak_error", opt(r.retroPeak)},
                                   {"sim_configs", r.simConfigs},
                                   {"sim_retro_energy_rms_error", opt(r.simEnergyRms)},
                                   {"sim_retro_energy_worst_error", opt(r.simEnergyWorst)},
                                   {"sim_retro_peak_rms_error", opt(r.simPeakRms)},
                                   {"sim_retro_peak_worst_error", opt(r.simPeakWorst)}});
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        auto e = [](double v) { return v >= 0 ? fmt_err(v) : std::string("-"); };
        auto signedPct = [](double v) {
            char b[32];
            std::snprintf(b, sizeof b, "%+.1f%%", 100 * v);
            return std::string(b);
        };
        std::printf("%-19s %-9s %-21s %7s %7s %8s %6s %9s %9s %9s %9s %15s %15s\n", "row", "tier",
                    "lobes", "ns/eval", "+pdf", "smp+pdf", "x MRM", "rel L1", "rel RMS",
                    "worst rel", "retro pk", "sim E rms/worst", "sim pk rms/worst");
        for (const Result& r : results) {
            const std::string simE = r.simConfigs > 0 ? plot::fmt("%.1f%%/", 100 * r.simEnergyRms) +
                                                            signedPct(r.simEnergyWorst)
                                                      : "-";
            const std::string simP = r.simConfigs > 0 ? plot::fmt("%.1f%%/", 100 * r.simPeakRms) +
                                                            signedPct(r.simPeakWorst)
                                                      : "-";
            std::printf("%-19s %-9s %-21s %7.1f %7s %8s %6.2f %9s %9s %9s %9s %15s %15s\n",
                        r.row->name.c_str(), r.row->tier.c_str(), r.row->lobes.c_str(), r.nsEval,
                        r.nsEvalPdf >= 0 ? fmt_num(r.nsEvalPdf).c_str() : "-",
                        r.nsSample >= 0 ? fmt_num(r.nsSample).c_str() : "-", r.ratio,
                        r.row->baseline ? "(other)" : e(r.error).c_str(), e(r.rms).c_str(),
                        e(r.worst).c_str(), e(r.retroPeak).c_str(), simE.c_str(), simP.c_str());
        }
        std::printf("\nconfigurations:\n");
        for (const Result& r : results)
            std::printf("  %-19s %s\n", r.row->name.c_str(), r.row->config.c_str());
        std::printf(
            "\nns/eval: f alone (rp_eval_f), single-threaded CPU time, the node's tiers and the "
            "baselines in float but `reference` (double); +pdf: f and the sampling pdf (rp_eval); "
            "smp+pdf: sample() with its pdf. Errors against the double reference over the "
            "standard direction pairs of `retroprism check` (360 per material); sim: retro energy "
            "and peak against the microgeometry simulator over docs/accuracy/results.csv "
            "(configurations with the row's prisms; the model's own error dominates). %u "
            "hardware threads.\n",
            std::thread::hardware_concurrency());
    }
    const std::string plotPath = ap["plot"].get<std::string>();
    if (!plotPath.empty()) write_plot(results, plotPath);
    if (ap["glsl"].get<int>()) glsl_costs(ap["json"].get<int>() != 0);
    return 0;
}

} // namespace retroprism
