// retroprism_bench: the node's benchmarks with Google Benchmark's own output (ns per iteration of
// bench::kPairs evaluations, items per second). `retroprism bench` prints the trade table.
#include <benchmark/benchmark.h>

#include "benchmarks.h"

int main(int argc, char** argv) {
    retroprism::bench::rows(); // registers the benchmarks
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
