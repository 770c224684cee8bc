// test_support.h: helpers shared by the tests: directions, a seeded generator, the
// chi-square distribution, the parameter corners every sweep uses, and running the command.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "prismatic_retroreflector.h"

namespace rptest {

using retroprism::Params;
using dvec3 = glm::dvec3;

// True in the instrumented builds (scripts/sanitize.sh, scripts/tsan.sh), where a few long
// sweeps take a subset of their points: there they are run for the sanitizers' reports, which
// the same code paths at fewer points give; the release suite runs every point.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kInstrumented = true;
#else
constexpr bool kInstrumented = false;
#endif

// Unit direction at polar angle theta and azimuth phi (degrees) in the local frame.
dvec3 dir_deg(double thetaDeg, double phiDeg);

// A fixed-seed generator (splitmix64): the same stream on every platform, unlike
// std::uniform_real_distribution.
class Rng {
  public:
    explicit Rng(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next_u64();
    // Uniform in [0, 1), 53 random bits.
    double uniform();

  private:
    std::uint64_t state_;
};

// Survival function P(X >= x) of the chi-square distribution with `dof` degrees of freedom
// (regularised upper incomplete gamma Q(dof/2, x/2)).
double chi2_sf(double x, double dof);

// Sidak-corrected per-test significance for `tests` tests at family significance `alpha`.
double sidak(double alpha, int tests);

// A named parameter set.
struct Corner {
    std::string name;
    Params params;
};
// The corners of the parameter space: roughness, ior, colours and every enum value.
std::vector<Corner> parameter_corners();

// A shell command's exit status (-1 when it did not exit normally) and its standard output and
// error together.
struct CommandRun {
    int status = -1;
    std::string output;
};
CommandRun run_command(const std::string& cmd);
// The retroprism command (RP_CLI_PATH) with `args`.
CommandRun run_cli(const std::string& args);

bool contains(const std::string& s, const std::string& part);

// The checked-in seeds of a fuzz target (fuzz/corpus/<target>/): each file's path and bytes.
struct CorpusFile {
    std::string path;
    std::vector<std::uint8_t> bytes;
};
std::vector<CorpusFile> fuzz_corpus(const std::string& target);

} // namespace rptest
