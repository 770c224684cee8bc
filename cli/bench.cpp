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
#include <string>
#include <thread>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <nlohmann/json.hpp>

#include "benchmarks.h"
#include "commands.h"
#include "gl_runner.h"
#include "glsl_gen.h"
#include "plot.h"
#include "query.h"

namespace retroprism {

namespace {

// Collects each benchmark's real time per iteration (ns).
class Collector : public benchmark::BenchmarkReporter {
  public:
    std::map<std::string, double> ns;
    bool ReportContext(const Context&) override { return true; }
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& r : runs) {
            if (r.error_occurred) continue;
            ns[r.benchmark_name()] = r.GetAdjustedCPUTime() *
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
    double nsEval = 0, nsSample = -1, ratio = 0, error = -1;
};

// The GLSL variants' relative cost: SPIR-V instructions after optimisation, and evaluations per
// second on this machine's OpenGL (llvmpipe without a GPU), excluding shader compilation.
void glsl_costs(const std::string& sourceDir, bool json) {
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
        const std::string lib = glsl::generate_library(v, sourceDir);
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
    using namespace plot;
    namespace IBA = OIIO::ImageBufAlgo;
    const int W = 1000, H = 640, left = 90, right = W - 40, top = 60, bottom = H - 80;
    OIIO::ImageBuf img(OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT));
    IBA::fill(img, {kBackground[0], kBackground[1], kBackground[2]});
    IBA::fill(img, {kPlotBackground[0], kPlotBackground[1], kPlotBackground[2]},
              OIIO::ROI(left, right, top, bottom));
    Text text("retroprism bench");
    // x: log10 ns per eval; y: log10 relative L1 error (rows without one are left out).
    std::vector<const Result*> pts;
    for (const Result& r : results)
        if (r.error > 0) pts.push_back(&r);
    double x0 = 1, x1 = 4, y0 = -8, y1 = 0;
    auto X = [&](double ns) {
        return int(left + (std::log10(ns) - x0) / (x1 - x0) * (right - left));
    };
    auto Y = [&](double e) {
        return int(bottom - (std::log10(e) - y0) / (y1 - y0) * (bottom - top));
    };
    for (int d = int(x0); d <= int(x1); ++d) {
        IBA::render_line(img, X(std::pow(10.0, d)), top, X(std::pow(10.0, d)), bottom, kGrid);
        text.draw(img, X(std::pow(10.0, d)), bottom + 22, fmt("%.0f ns", std::pow(10.0, d)), 15,
                  kDimText, IBA::TextAlignX::Center);
    }
    for (int d = int(y0); d <= int(y1); d += 2) {
        IBA::render_line(img, left, Y(std::pow(10.0, d)), right, Y(std::pow(10.0, d)), kGrid);
        text.draw(img, left - 8, Y(std::pow(10.0, d)) + 5, fmt("1e%.0f", d), 15, kDimText,
                  IBA::TextAlignX::Right);
    }
    // The Pareto front: rows no other row beats in both cost and error.
    std::vector<const Result*> front;
    for (const Result* p : pts) {
        bool dominated = false;
        for (const Result* q : pts)
            if (q != p && q->nsEval <= p->nsEval && q->error <= p->error &&
                (q->nsEval < p->nsEval || q->error < p->error))
                dominated = true;
        if (!dominated) front.push_back(p);
    }
    std::sort(front.begin(), front.end(),
              [](const Result* a, const Result* b) { return a->nsEval < b->nsEval; });
    for (size_t i = 1; i < front.size(); ++i)
        thick_line(img, X(front[i - 1]->nsEval), Y(front[i - 1]->error), X(front[i]->nsEval),
                   Y(front[i]->error), kLobeColor[1], 2, OIIO::ROI(left, right, top, bottom));
    for (const Result* p : pts) {
        const bool onFront = std::find(front.begin(), front.end(), p) != front.end();
        dot(img, X(p->nsEval), Y(p->error), 5, onFront ? kLobeColor[1] : kLobeColor[0],
            OIIO::ROI(left, right, top, bottom));
        text.draw(img, X(p->nsEval) + 8, Y(p->error) - 6, p->row->name, 13, kText);
    }
    for (const Result& r : results)
        if (r.row->name == "mrm_ggx") {
            IBA::render_line(img, X(r.nsEval), top, X(r.nsEval), bottom, kLobeColor[2]);
            text.draw(img, X(r.nsEval) + 4, top + 16, "MaterialX retro GGX", 14, kLobeColor[2]);
        }
    text.draw(img, 30, 36,
              "retroprism: cost (ns per eval, float unless reference) vs relative L1 error "
              "against the double reference; Pareto front in orange",
              17, kText);
    text.draw(img, (left + right) / 2, H - 24, "ns per evaluation (log)", 16, kDimText,
              IBA::TextAlignX::Center);
    if (!img.write(path))
        throw InputError(path + ": cannot write the plot (" + img.geterror() + ")");
}

} // namespace

int cmd_bench(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism bench: the speed/accuracy trade table (Google Benchmark, this machine)")
        .usage("retroprism bench [--json] [--plot OUT.png] [--min-time SECONDS] [--glsl]");
    ap.arg("--json").help("print the rows as JSON").store_true();
    ap.arg("--glsl")
        .help("also the GLSL variants' SPIR-V size and llvmpipe throughput")
        .store_true();
    ap.arg("--plot OUT.png").help("write the cost-error plot with the Pareto front");
    ap.arg("--min-time SECONDS")
        .dest("min_time")
        .help("minimum time per benchmark (default 0.2)")
        .defaultval("0.2");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    const std::string minTime = ap["min_time"].get<std::string>();
    char* end = nullptr;
    const double mt = std::strtod(minTime.c_str(), &end);
    if (*end != '\0' || !(mt > 0 && mt <= 60))
        throw InputError("--min-time " + minTime + ": expected seconds in (0, 60]");

    const std::vector<bench::Row>& rows = bench::rows();
    std::string flag = "--benchmark_min_time=" + minTime;
    std::vector<char*> bargs = {const_cast<char*>("retroprism"), flag.data()};
    int bargc = int(bargs.size());
    benchmark::Initialize(&bargc, bargs.data());
    Collector collector;
    benchmark::RunSpecifiedBenchmarks(&collector);

    std::vector<Result> results;
    double mrm = 0;
    for (const bench::Row& r : rows) {
        Result res;
        res.row = &r;
        res.nsEval = collector.ns["eval/" + r.name] / bench::kPairs;
        if (r.has_sample) res.nsSample = collector.ns["sample_pdf/" + r.name] / bench::kPairs;
        res.error = r.error();
        if (r.name == "mrm_ggx") mrm = res.nsEval;
        results.push_back(res);
    }
    for (Result& r : results)
        r.ratio = mrm > 0 ? r.nsEval / mrm : 0;

    if (ap["json"].get<int>()) {
        nlohmann::json out = {{"rows", nlohmann::json::array()}};
        for (const Result& r : results)
            out["rows"].push_back(
                {{"name", r.row->name},
                 {"tier", r.row->tier},
                 {"lobes", r.row->lobes},
                 {"config", r.row->config},
                 {"ns_per_eval", r.nsEval},
                 {"ns_per_sample_pdf",
                  r.nsSample >= 0 ? nlohmann::json(r.nsSample) : nlohmann::json(nullptr)},
                 {"ratio_to_mrm", r.ratio},
                 {"rel_l1_error",
                  r.error >= 0 ? nlohmann::json(r.error) : nlohmann::json(nullptr)}});
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("%-20s %-10s %-22s %10s %12s %9s %12s  %s\n", "row", "tier", "lobes", "ns/eval",
                    "ns/smp+pdf", "x MRM", "rel L1 err", "configuration");
        for (const Result& r : results) {
            std::printf("%-20s %-10s %-22s %10.1f %12s %9.2f %12s  %s\n", r.row->name.c_str(),
                        r.row->tier.c_str(), r.row->lobes.c_str(), r.nsEval,
                        r.nsSample >= 0 ? fmt_num(r.nsSample).c_str() : "-", r.ratio,
                        r.error >= 0 ? fmt_err(r.error).c_str() : "(other model)",
                        r.row->config.c_str());
        }
        std::printf(
            "(%u hardware threads, benchmarks single-threaded, CPU time; the node's tiers are "
            "float but `reference`, the baselines are double)\n",
            std::thread::hardware_concurrency());
    }
    const std::string plotPath = ap["plot"].get<std::string>();
    if (!plotPath.empty()) write_plot(results, plotPath);
    if (ap["glsl"].get<int>()) glsl_costs(RP_SOURCE_DIR_CLI, ap["json"].get<int>() != 0);
    return 0;
}

} // namespace retroprism
