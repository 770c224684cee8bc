// study.h: the accuracy study (MODEL.md section 6): every analytic variant of the node
// (retro_lobe isotropic | anisotropic x reciprocal false | true) against the microgeometry
// simulator over a grid of incidence angles, roughnesses, iors and prism modes; the paper's way
// up for the diffuse lobe; cone-to-cone reciprocity runs. The metrics are defined here; the
// document and its plots are report/accuracy_report.h.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "microgeometry.h"

namespace retroprism::sim {

// ---- The study's grid -----------------------------------------------------------------------

// An analytic variant: the node with retro_lobe `aniso` and reciprocal `recip`.
struct Variant {
    const char* name; // as the document names it
    const char* key;  // as the CSV columns and the findings name it
    int aniso;
    int recip;
};
inline const Variant kVariants[4] = {{"isotropic (paper)", "iso", 0, 0},
                                     {"anisotropic", "aniso", 1, 0},
                                     {"isotropic + reciprocal", "iso+rec", 0, 1},
                                     {"anisotropic + reciprocal", "aniso+rec", 1, 1}};

constexpr double kStudyKd = 0.9;        // diffuse_color of every configuration
constexpr double kRecipConeDeg = 4.0;   // reciprocity: cones of incidence and exit
constexpr double kDiffuseConeDeg = 5.0; // diffuse-level cones
constexpr double kResolvedSe = 0.05;    // a metric counts when the simulation knows it to 5%
constexpr double kDiffuseAlpha = 0.1;   // roughness of the diffuse-model comparison
// The grids of run_config: sim::standard_grids, then the two diffuse-level cones.
constexpr int kGridRetro = 0, kGridMirror = 1, kGridHemi = 2, kGridInPlane = 3, kGridNormal = 5,
              kGridD60 = 6;

// The configurations of a study: the full grid, or --quick's smoke-test subset.
struct StudyGrid {
    std::vector<double> thetas, alphas, etas;
    std::vector<int> prisms;
    size_t size() const { return thetas.size() * alphas.size() * etas.size() * prisms.size(); }
};
StudyGrid study_grid(bool quick);

struct Config {
    double theta, alpha, eta; // theta_i [deg], roughness, ior
    int prism;                // f64::RP_PRISM_*
};

// "tir", "metallized" or "ideal" (the node's enum names).
const char* prism_name(int prism);
// The prism mode of a name of prism_name; -1 for none.
int prism_of_name(const std::string& name);
// "20 deg, alpha 0.1, eta 1.49, tir".
std::string config_label(const Config& c);
// "0.1/1.49/tir".
std::string material_key(double alpha, double eta, int prism);
// The node's inputs of variant `variant` (kVariants) at configuration c.
Params config_params(const Config& c, int variant);
// theta [deg], phi [deg] as a unit vector of the local frame (n = +z).
dvec3 direction_deg(double thetaDeg, double phiDeg);

// ---- One configuration ------------------------------------------------------------------------

struct VariantResult {
    double alphaPar = 0, alphaPerp = 0; // the variant's lobe widths at wi
    LobeFit fit;                        // fitted on the simulation's cells, with its weights
    double peak = 0, energy = 0, surface = 0, diffuseNormal = 0, diffuse60 = 0, diffuseAlbedo = 0;
    double l1 = 0, l1Retro = 0;
    std::vector<double> row, col;             // f_r on the retro grid's centre row / column
    std::array<std::vector<double>, 4> strip; // in-plane f: surface, retro, diffuse, total
};

struct SimResult {
    std::uint64_t rays = 0;
    double seconds = 0;
    int threads = 1;
    LobeFit fit;
    Estimate peak, energy, energyPrimary, energyMultiple, diffuseNormal, diffuse60, diffuseAlbedo,
        surface, surfaceSingle, absorbed;
    std::uint64_t trapped = 0;
    double l1Noise = 0, l1RetroNoise = 0;
    std::vector<double> rowX, colX, stripX; // degrees
    std::vector<Estimate> row, col;
    std::array<std::vector<Estimate>, 4> strip;
    double hx = 0, hy = 0; // retro grid half-widths (slopes)
};

struct ConfigResult {
    Config c{};
    SimResult sim;
    std::array<VariantResult, 4> v;
};

// Simulates configuration `cfg` (phi_i = 0) with `rays` rays and, when `analytic`, integrates the
// four variants over the same cells. throughPrisms: the simulator's reciprocal way up, else the
// paper's (substrate light straight to the top surface).
ConfigResult run_config(const Config& cfg, std::uint64_t rays, std::uint64_t seed,
                        bool throughPrisms, bool analytic, int threads,
                        const RunOptions::Progress& progress = {});

// ---- Reciprocity ----------------------------------------------------------------------------

// The 11 probe directions of the reciprocity runs: every study theta_i at phi 0 and 180.
struct ProbeDir {
    double theta, phi; // degrees
};
std::vector<ProbeDir> probe_dirs();

// One pair of cones A, B of the reciprocity runs: Q(A, B) = integral over A x B of
// f cos cos, estimated from the run with incidence spread over A (qab) and from the run with
// incidence spread over B (qba).
struct RecipPair {
    double alpha = 0, eta = 0;
    int prism = 0, a = 0, b = 0; // a, b: indices into probe_dirs()
    Estimate qab, qba;
};

// z of a pair under the hypothesis Q(A, B) = Q(B, A) = their mean Q: the count of the run over
// A is binomial with mean N Q / Omega_p(A), so var(Q_ab) = Omega_p(A) Q (1 - Q / Omega_p(A)) / N
// (the errors of the observed counts would understate the variance of low counts that
// fluctuated down). rays: N per cone of incidence.
double reciprocity_z(const RecipPair& q, std::uint64_t rays);

// ---- The whole study ------------------------------------------------------------------------

struct StudyOptions {
    std::uint64_t rays = 4000000;        // per configuration
    std::uint64_t diffuseRays = 1000000; // per configuration of the paper's way up
    std::uint64_t recipRays = 400000;    // per cone of incidence of the reciprocity runs
    std::uint64_t seed = 2018;           // configuration k uses seed + k
    int threads = 0;
    bool quick = false;
};

// The roughness of the diffuse-model runs of a study (--quick: its one roughness).
double diffuse_alpha(bool quick);

// The results of a study. Run metadata: machine, date, simSeconds, elapsed, threadsUsed and each
// simulation's seconds and threads (SimResult) describe how and where it ran, not what it found;
// everything else is a result, the same bits for the same options on any machine, with any
// number of threads or shards.
struct StudyResults {
    StudyOptions options;
    StudyGrid grid;
    std::string machine, date; // of the run that simulated (metadata)
    double simSeconds = 0, simRays = 0, elapsed = 0;
    int threadsUsed = 1;
    std::vector<ConfigResult> results; // by eta, prism, alpha, theta
    std::vector<ConfigResult> direct;  // the paper's way up at kDiffuseAlpha, by eta, prism, theta
    std::vector<RecipPair> pairs;
    // The roughness of the diffuse-model runs (--quick: its one roughness).
    double diffuse_alpha() const;
    // The result of a configuration of the grid (InputError when there is none).
    const ConfigResult& at(double theta, double alpha, double eta, int prism) const;
};

// The study's results without their run metadata (StudyResults): those fields zero or empty, so
// that two runs of the same study compare equal field by field and number by number.
StudyResults without_metadata(StudyResults s);

// What a study run reports while it runs: a progress callback per simulation (from its label),
// and each configuration as it is done.
struct StudyObserver {
    std::function<RunOptions::Progress(const std::string& label)> progress;
    std::function<void(const ConfigResult&)> config_done;
};

// ---- Work units and shards --------------------------------------------------------------------
// A study is a fixed list of work units, each simulated alone from its own seed: every
// configuration (seed + k for the k-th, by eta, prism, alpha, theta), every configuration of the
// paper's way up (seed + 100000 + k, k counting on after the configurations, by eta, prism,
// theta) and the reciprocity runs of every material (seed + 200000 + 100 m for the m-th, by eta,
// prism, alpha; its 11 cones of incidence seed + 200000 + 100 m + a). A shard K/N runs the units
// shard_assignment gives it; merge_study_shards puts N shards' units back in their order, and
// the whole study is the one shard 1/1, so a sharded study has the same results, bit for bit.

enum class UnitKind { Config, Direct, Reciprocity };

struct StudyUnit {
    UnitKind kind;
    Config c;               // Reciprocity: the material (theta 0)
    std::uint64_t seed = 0; // of its (first) simulation
    std::uint64_t rays = 0; // rays it simulates: the shards' balance
};

// The work units of a study, in their fixed order.
std::vector<StudyUnit> study_units(const StudyOptions& options);

// Shard K of N, 1 <= K <= N.
struct ShardSpec {
    int k = 1, n = 1;
};

// "K/N" as a shard of a study of `units` work units: InputError `<what> <text>: ...` naming the
// allowed range unless K and N are whole numbers with 1 <= K <= N <= units.
ShardSpec parse_shard(const std::string& text, const std::string& what, size_t units);

// The shard (1..n) of each unit: the units by decreasing rays (ties in their order) each to the
// shard with the fewest rays so far (ties to the lowest K). It depends on the units' ray counts
// and n only, never on the machine or the threads.
std::vector<int> shard_assignment(const std::vector<StudyUnit>& units, int n);

// One unit's results: a configuration (Config, Direct) or the pairs of a material
// (Reciprocity). seconds is run metadata.
struct UnitResult {
    size_t index = 0; // into study_units
    std::uint64_t rays = 0;
    double seconds = 0;
    ConfigResult config;
    std::vector<RecipPair> pairs;
};

// The partial results of one shard (sim/study_results.h writes and reads them). machine, date,
// simSeconds, elapsed, threadsUsed and the units' seconds are run metadata.
struct StudyShard {
    StudyOptions options;
    ShardSpec shard;
    std::string source; // the file it was read from, for the merge's errors ("" when run here)
    std::string machine, date;
    double simSeconds = 0, elapsed = 0;
    int threadsUsed = 1;
    std::vector<UnitResult> units; // its units, in their order
};

// Runs the units of shard `shard` of the study.
StudyShard run_study_shard(const StudyOptions& options, ShardSpec shard,
                           const StudyObserver& observer = {});

// The study from all N shards of it (in any order). InputError naming the offending file when the
// shards are not of one study (options, grid or N differ), a shard is missing or given twice, or
// a shard holds other units than its own. The results are the units' in their order; of the
// metadata, the seconds of simulation add up, elapsed is the longest shard's, threadsUsed the
// most any shard used, and machine and date name each shard's when there are several.
StudyResults merge_study_shards(const std::vector<StudyShard>& parts);

// The whole study: merge_study_shards of the one shard 1/1.
StudyResults run_study(const StudyOptions& options, const StudyObserver& observer = {});

// The relative asymmetries of the reciprocity test: the simulation's z-scores and relative
// differences of its pairs, and every variant's relative asymmetry |f(a, b) - f(b, a)| / mean at
// the same pairs of directions (wide) and at pairs near the retro peak (near).
struct Reciprocity {
    std::vector<double> z, rel;
    std::array<std::vector<double>, 4> wide, near;
};
Reciprocity analyse_reciprocity(const StudyResults& s);

// ---- Metrics ----------------------------------------------------------------------------------

// The relative standard error of an estimate (huge when the value is 0).
double rel_se(const Estimate& e);
// Whether the simulation's fitted width along (par) or across the plane is known to kResolvedSe.
bool width_resolved(const SimResult& s, bool par);
// Variant v's fitted width / the simulation's - 1 (NaN without fits).
double width_err(const ConfigResult& r, int v, bool par);
// Variant v's retro energy / the simulation's - 1.
double energy_err(const ConfigResult& r, int v);

// The worst (largest |value|) of a metric over a set of configurations, with where it is.
struct Worst {
    double value = 0;
    bool any = false;
    std::string where;
    int counted = 0, unresolved = 0;
    void add(double v, bool resolved, const std::string& w);
};

// The study's statistics of a list: the median (mean of the two middle values of an even
// count; NaN when empty), the largest |x| (NaN when empty), the root mean square (NaN when
// empty).
double median_of(std::vector<double> v);
double max_abs(const std::vector<double>& v);
double rms(const std::vector<double>& v);

} // namespace retroprism::sim
