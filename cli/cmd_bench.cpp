// cmd_bench.cpp: `retroprism bench`, the speed/accuracy trade table, from the Google Benchmark
// benchmarks of bench/benchmarks.cpp run in this process: ns per evaluation and per sample + pdf of
// each fidelity tier and lobe set, the ratio to the MaterialX-style retroreflective GGX, and each
// row's relative L1 error against the double reference; a cost-error plot with the Pareto front.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <thread>

#include <OpenImageIO/imagebuf.h>

#include <nlohmann/json.hpp>

#include "benchmarks.h"
#include "commands.h"
#include "cost_error_plot.h"
#include "error.h"
#include "parse.h"
#include "paths.h"
#include "plot.h"
#include "mx_cost.h"
#include "trade.h"

namespace retroprism {

namespace {

using bench::Result;
using bench::SimConfig;

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

// Two timings per material (bench::PairedRow): its two benchmarks' times, each over `per` (ns
// per unit: 1e6 for ms per node, kPairs for ns per shading point).
struct Paired {
    const bench::PairedRow* row;
    double first, second;
};

std::vector<Paired> paired_of(Collector& collector, const std::vector<bench::PairedRow>& rows,
                              double per) {
    std::vector<Paired> out;
    for (const bench::PairedRow& c : rows)
        out.push_back({&c, collector.ns[c.first] / per, collector.ns[c.second] / per});
    return out;
}

// The paired timings as JSON rows: name, config and the two timings under the keys given.
nlohmann::json paired_json(const std::vector<Paired>& rows, const char* first, const char* second) {
    nlohmann::json out = nlohmann::json::array();
    for (const Paired& c : rows)
        out.push_back({{"name", c.row->name},
                       {"config", c.row->config},
                       {first, c.first},
                       {second, c.second}});
    return out;
}

// The table of paired timings, each row with the ratio first / second.
void print_paired(const std::vector<Paired>& rows, const char* title, const char* first,
                  const char* second, const char* ratio, const char* format) {
    std::printf("\n%-26s %10s %10s %9s  %s\n", title, first, second, ratio, "material");
    for (const Paired& c : rows)
        std::printf(format, c.row->name.c_str(), c.first, c.second,
                    c.second > 0 ? c.first / c.second : 0.0, c.row->config.c_str());
}

// The GLSL variants' cost and MaterialX's own generated shaders' (bench/mx_cost.h), as tables
// or JSON, each SPIR-V size also as a ratio to MaterialX's dielectric + Oren-Nayar shader's:
// over all instructions, and over the code alone (without the constants' declarations, where
// the node's tables are).
void print_glsl_costs(bool json) {
    const std::vector<bench::GlslCost> variants = bench::glsl_costs();
    const std::vector<bench::MxShaderCost> mx = bench::mx_shader_costs(data_dir());
    long baseAll = -1, baseCode = -1;
    for (const bench::MxShaderCost& c : mx)
        if (c.material == "dielectric_oren_nayar") {
            baseAll = c.spirvInstructions;
            baseCode = c.spirvInstructions - c.spirvConstants;
        }
    auto ratio = [](long n, long base) { return base > 0 && n > 0 ? double(n) / base : 0.0; };
    nlohmann::json rows = nlohmann::json::array(), mxRows = nlohmann::json::array();
    const char* head = "\n%-52s %14s %10s %9s %9s %16s\n";
    const char* row = "%-52s %14ld %10ld %9.3f %9.3f %16.3g\n";
    auto add = [&](nlohmann::json& rowsOut, const std::string& key, const std::string& name,
                   long all, long constants, const char* rateKey, double rate) {
        const double rAll = ratio(all, baseAll), rCode = ratio(all - constants, baseCode);
        if (json)
            rowsOut.push_back({{key, name},
                               {"spirv_instructions", all},
                               {"spirv_constants", constants},
                               {"ratio_to_mx_dielectric_oren_nayar", rAll},
                               {"code_ratio_to_mx_dielectric_oren_nayar", rCode},
                               {rateKey, rate}});
        else
            std::printf(row, name.c_str(), all, constants, rAll, rCode, rate);
    };
    if (!json)
        std::printf(head, "GLSL variant", "SPIR-V instr.", "constants", "x MX all", "x MX code",
                    "llvmpipe eval/s");
    for (const bench::GlslCost& c : variants)
        add(rows, "variant", c.variant, c.spirvInstructions, c.spirvConstants,
            "llvmpipe_evals_per_second", c.evalsPerSecond);
    if (!json)
        std::printf(head, "MaterialX 1.39.4's generated fragment shader", "SPIR-V instr.",
                    "constants", "x MX all", "x MX code", "llvmpipe pixel/s");
    for (const bench::MxShaderCost& c : mx)
        add(mxRows, "material", c.material, c.spirvInstructions, c.spirvConstants,
            "llvmpipe_pixels_per_second", c.pixelsPerSecond);
    if (json)
        std::printf("%s\n", nlohmann::json{{"glsl", rows}, {"materialx", mxRows}}.dump(2).c_str());
    else
        std::printf("(x MX: SPIR-V instructions after spirv-opt -O over those of MaterialX's "
                    "fragment shader for dielectric_bsdf over oren_nayar_diffuse_bsdf, all of "
                    "them or the code alone, without the constants' declarations; MaterialX's "
                    "shaders are whole surface shaders, timed per pixel of the same 512 x 512 "
                    "plane under one directional light)\n");
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

    const std::vector<SimConfig> study = bench::read_study(data_path("docs/accuracy/results.csv"));
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
            bench::reference_errors(r, res);
            bench::simulator_errors(r, study, res);
        }
        if (r.name == "mrm_ggx") mrm = res.nsEval;
        results.push_back(res);
    }
    for (Result& r : results)
        r.ratio = mrm > 0 ? r.nsEval / mrm : 0;

    const std::vector<Paired> constructions = paired_of(collector, bench::construction_rows(), 1e6);
    const std::vector<Paired> shadings = paired_of(collector, bench::shading_rows(), bench::kPairs);

    auto opt = [](double v) { return v >= 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
    if (ap["json"].get<int>()) {
        nlohmann::json out = {
            {"rows", nlohmann::json::array()},
            {"construction", paired_json(constructions, "ms_made", "ms_kept")},
            {"shading_point", paired_json(shadings, "ns_from_wi", "ns_from_state")}};
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
        print_paired(constructions, "node construction", "ms made", "ms kept", "made/kept",
                     "%-26s %10.3f %10.4f %9.0f  %s\n");
        std::printf("(made: a material not made before in the process, its azimuth-average series "
                    "made; kept: one made before, its series copied from those the process keeps, "
                    "the last %d)\n",
                    kSeriesCacheEntries);
        print_paired(shadings, "shading point", "ns from wi", "ns state", "wi/state",
                     "%-26s %10.1f %10.1f %9.2f  %s\n");
        std::printf("(a shading point: %d light samples evaluated with their pdf and one BSDF "
                    "sample at one incident direction, float node; from wi: each call passes wi; "
                    "state: incident(wi) made once, each call passes it)\n",
                    bench::kShadingLights);
    }
    const std::string plotPath = ap["plot"].get<std::string>();
    if (!plotPath.empty()) write_plot(results, plotPath);
    if (ap["glsl"].get<int>()) print_glsl_costs(ap["json"].get<int>() != 0);
    return 0;
}

} // namespace retroprism
