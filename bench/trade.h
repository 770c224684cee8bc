// trade.h: the speed/accuracy trade table's figures beside the benchmarks' times: each row's
// error against the double reference over the standard direction pairs of `retroprism check`,
// its retro lobe against the microgeometry simulator (docs/accuracy/results.csv), and the GLSL
// variants' cost (SPIR-V size, llvmpipe throughput), and the choice of the cheapest variant for
// a material within an error. `retroprism bench` and `export` print them.
#pragma once

#include <string>
#include <vector>

#include "benchmarks.h"

namespace retroprism::bench {

struct Result {
    const Row* row;
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
void reference_errors(const Row& row, Result& res);

// One configuration of the simulator's accuracy study.
struct SimConfig {
    double thetaDeg, roughness, ior;
    int prism;
    double simPeak, simEnergy; // simulated: retro peak (1/sr, cell average), retro energy
    double modelPeak;          // the double reference's peak averaged over the same cells
};

// The study's configurations from its results file (sim/study_results.h).
std::vector<SimConfig> read_study(const std::string& path);

// The row's retro lobe against the simulator, over the study's configurations with the row's
// prisms (the study's material: kd 0.9, isotropic lobe, the paper's form; phi_i = 0); none for
// a row whose prisms are not the paper's cube (cant_angle, dihedral errors). Energy:
// the row's retro albedo, integrated over the double reference's retro sampling map (64 x 64
// midpoints, weights f cos / pdf), against the simulated retro fraction. Peak: the study's
// cell-averaged reference peak scaled by the row's peak over the reference's at wo = wi.
void simulator_errors(const Row& row, const std::vector<SimConfig>& study, Result& res);

// One GLSL variant's relative cost: SPIR-V instructions after optimisation, and evaluations per
// second on this machine's OpenGL (llvmpipe without a GPU), excluding shader compilation.
struct GlslCost {
    std::string variant;
    long spirvInstructions = -1;
    long spirvConstants = -1; // of spirvInstructions, those declaring constants (table data)
    double evalsPerSecond = 0;
};
std::vector<GlslCost> glsl_costs();

// Relative L1 error of the node with `p` against the same node in the exact tier (double),
// over the check query set's directions (sum |f - f_exact| / sum |f_exact|).
double fidelity_error(const Params& p);

// The cheapest generated variant for a material whose error stays within maxError (`retroprism
// export --max-error`): variants that fix a mode the material does not use, or leave out a
// lobe it has, are out; the fast tier's error is measured for the material; cost is the SPIR-V
// instruction count. `chosen` is empty when no variant fits.
struct VariantCandidate {
    std::string variant;
    long spirvInstructions = -1;
    double error = 0;
};
struct VariantChoice {
    double fastError = 0;
    std::vector<VariantCandidate> candidates; // in the order of glsl::standard_variants()
    std::string chosen;
    long chosenCost = -1;
};
VariantChoice choose_variant(const Params& p, double maxError);

} // namespace retroprism::bench
