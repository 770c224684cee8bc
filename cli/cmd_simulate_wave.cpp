// cmd_simulate_wave.cpp: `retroprism simulate --wave`, the physical-optics ground truth of the
// retro lobe (sim/wave_optics.h, docs/wave_optics.md) as a table of R_A against observation angle;
// with --against-node the node's lobe beside it (sim/wave_node.h), as a table and a figure.
#include <cstdio>
#include <string>
#include <vector>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "error.h"
#include "figure.h"
#include "parse.h"
#include "query.h"
#include "wave_node.h"
#include "wave_optics.h"
#include "wave_report.h"

namespace retroprism {

namespace {

sim::wave::WaveMode mode_option(const Params& p, OIIO::ArgParse& ap) {
    sim::wave::WaveMode mode = sim::wave::wave_mode(p);
    const std::string era = ap["era"].get<std::string>();
    if (era == "averaged")
        mode.era = sim::wave::WaveMode::Era::kAveraged;
    else if (era == "matched_pair")
        mode.era = sim::wave::WaveMode::Era::kMatchedPair;
    else if (era == "oriented")
        mode.era = sim::wave::WaveMode::Era::kOriented;
    else if (!era.empty())
        throw InputError("--era " + era + ": expected averaged, matched_pair or oriented");
    const std::string rotations = ap["rotation"].get<std::string>();
    if (!rotations.empty())
        mode.rotations_deg = parse_number_list(rotations, "--rotation", -360, 360);
    mode.coplanar = ap["coplanar"].get<int>() != 0;
    mode.pitch_spread =
        parse_number_in(ap["pitch_spread"].get<std::string>(), "--pitch-spread", 0, 0.5);
    return mode;
}

} // namespace

int simulate_wave_command(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism simulate --wave: R_A (cd lx^-1 m^-2) of the prisms alone in physical "
             "optics (docs/wave_optics.md): each cube corner's exit pupil face order by face "
             "order (TIR phases, metal, dihedral errors), its Fraunhofer far field, prisms summed "
             "over the era mode's orientations, averaged over the observation azimuth (or the "
             "coplanar observation of `retroprism ra`).")
        .usage("retroprism simulate --wave [--material FILE.json] [--pitch UM] [--entrance "
               "DEG,...] [--observation DEG,...] [--wavelength NM,... | --photopic] [--era MODE] "
               "[--rotation DEG,...] [--pitch-spread S] [--coplanar] [--against-node [--plot "
               "FILE.png]]");
    ap.arg("--wave").help("the physical-optics R_A table").store_true();
    ap.arg("--material FILE").help("node inputs as a JSON object (default: all defaults)");
    ap.arg("--pitch UM")
        .help("groove spacing in micrometres: the height of the aperture triangle, [1, 1e5] "
              "(default 150)")
        .defaultval("150");
    ap.arg("--entrance DEG,...")
        .help("entrance angles in degrees, [-85, 85] (default -4,30)")
        .defaultval("-4,30");
    ap.arg("--observation DEG,...")
        .help("observation angles in degrees, (0, 20] (default 0.1,0.2,0.33,0.5,0.7,1,1.5,2)")
        .defaultval("0.1,0.2,0.33,0.5,0.7,1,1.5,2");
    ap.arg("--wavelength NM,...")
        .help("wavelengths in nm, [200, 20000] (default 550)")
        .defaultval("550");
    ap.arg("--photopic")
        .help("weight 15 wavelengths 410-690 nm by illuminant A x V(lambda) instead")
        .store_true();
    ap.arg("--era MODE")
        .help("averaged, matched_pair or oriented (default: the material's era_mode)");
    ap.arg("--rotation DEG,...")
        .help("rotation angles of matched_pair and oriented, averaged (default: the material's "
              "orientation; datasheets: 0,90)");
    ap.arg("--pitch-spread S")
        .dest("pitch_spread")
        .help("pitches uniform over pitch (1 +- S), S in [0, 0.5] (default 0: one pitch)")
        .defaultval("0");
    ap.arg("--coplanar")
        .help("the coplanar observation of `retroprism ra` instead of the azimuth mean")
        .store_true();
    ap.arg("--against-node")
        .dest("against_node")
        .help("the node's R_A (smooth, the retro lobe alone) beside the wave optics' and their "
              "ratio, at the material's era_mode (docs/diffraction.md)")
        .store_true();
    ap.arg("--plot FILE").help("with --against-node: R_A against observation 0.05-3 deg (PNG)");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    Params p;
    const std::string file = ap["material"].get<std::string>();
    if (!file.empty()) p = params_from_json(read_json(file), file);
    const double pitch = parse_number_in(ap["pitch"].get<std::string>(), "--pitch", 1, 1e5);
    const sim::wave::WaveMaterial m = sim::wave::wave_material(p, pitch);
    sim::wave::check_material(m);
    const sim::wave::WaveMode mode = mode_option(p, ap);
    const std::vector<double> entrance =
        parse_number_list(ap["entrance"].get<std::string>(), "--entrance", -85, 85);
    const std::vector<double> obs =
        parse_number_list(ap["observation"].get<std::string>(), "--observation", 1e-9, 20);
    const bool photopic = ap["photopic"].get<int>() != 0;
    const std::vector<double> lambdas =
        photopic
            ? std::vector<double>{0.0}
            : parse_number_list(ap["wavelength"].get<std::string>(), "--wavelength", 200, 20000);
    const std::string plotPath = ap["plot"].get<std::string>();
    if (ap["against_node"].get<int>() != 0) {
        if (photopic || mode.coplanar || !ap["era"].get<std::string>().empty() ||
            !ap["rotation"].get<std::string>().empty())
            throw InputError("--against-node: at --wavelength, the azimuth mean, the material's "
                             "era_mode (no --photopic, --coplanar, --era or --rotation)");
        std::vector<sim::wave::NodeWaveCase> cases;
        for (double e : entrance)
            for (double nm : lambdas)
                cases.push_back({p.prism_reflection, pitch, nm, e});
        print_node_wave(p, sim::wave::node_wave_profiles(p, cases, obs, mode.pitch_spread), obs,
                        mode.pitch_spread, stdout);
        if (plotPath.empty()) return 0;
        plot::Text text("retroprism simulate");
        plot::write_png(plot::node_wave_figure(
                            p,
                            sim::wave::node_wave_profiles(
                                p, cases, plot::node_wave_plot_observations(), mode.pitch_spread),
                            mode.pitch_spread, text),
                        plotPath);
        std::printf("wrote %s\n", plotPath.c_str());
        return 0;
    }
    if (!plotPath.empty()) throw InputError("--plot: only with --against-node");
    std::vector<std::vector<std::vector<double>>> ra; // [wavelength][entrance][observation]
    for (double lambda : lambdas) {
        ra.emplace_back();
        for (double e : entrance)
            ra.back().push_back(photopic ? sim::wave::wave_ra_profile_photometric(m, e, obs, mode)
                                         : sim::wave::wave_ra_profile(m, e, obs, lambda, mode));
    }
    print_wave_table(m, lambdas, entrance, obs, ra, stdout);
    return 0;
}

} // namespace retroprism
