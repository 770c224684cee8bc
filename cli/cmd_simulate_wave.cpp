// cmd_simulate_wave.cpp: `retroprism simulate --wave`, the physical-optics ground truth of the
// retro lobe (sim/wave_optics.h, docs/wave_optics.md) as a table of R_A against observation angle.
#include <cstdio>
#include <string>
#include <vector>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "error.h"
#include "parse.h"
#include "query.h"
#include "wave_optics.h"

namespace retroprism {

namespace {

// A comma-separated list of numbers in [lo, hi] (option `what`).
std::vector<double> number_list(const std::string& text, const std::string& what, double lo,
                                double hi) {
    std::vector<double> list;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = std::min(text.find(',', start), text.size());
        list.push_back(parse_number_in(text.substr(start, comma - start), what, lo, hi));
        start = comma + 1;
    }
    return list;
}

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
    if (!rotations.empty()) mode.rotations_deg = number_list(rotations, "--rotation", -360, 360);
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
               "[--rotation DEG,...] [--pitch-spread S] [--coplanar]");
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
        number_list(ap["entrance"].get<std::string>(), "--entrance", -85, 85);
    const std::vector<double> obs =
        number_list(ap["observation"].get<std::string>(), "--observation", 1e-9, 20);
    const bool photopic = ap["photopic"].get<int>() != 0;
    const std::vector<double> lambdas =
        photopic ? std::vector<double>{0.0}
                 : number_list(ap["wavelength"].get<std::string>(), "--wavelength", 200, 20000);
    std::printf("# wave R_A (sr^-1): ior %g, prism_reflection %d, cant %g deg, dihedral %g', "
                "pitch %g um\n",
                m.ior, m.prism_reflection, m.cant_deg, m.dihedral_arcmin, m.pitch_um);
    for (double lambda : lambdas) {
        std::vector<std::vector<double>> columns;
        for (double e : entrance)
            columns.push_back(photopic ? sim::wave::wave_ra_profile_photometric(m, e, obs, mode)
                                       : sim::wave::wave_ra_profile(m, e, obs, lambda, mode));
        std::printf(photopic ? "# photopic (illuminant A x V)\n" : "# %g nm\n", lambda);
        std::printf("%12s", "obs\\entr");
        for (double e : entrance)
            std::printf(" %11g", e);
        std::printf("\n");
        for (size_t a = 0; a < obs.size(); ++a) {
            std::printf("%12g", obs[a]);
            for (const std::vector<double>& c : columns)
                std::printf(" %11.5g", c[a]);
            std::printf("\n");
        }
    }
    return 0;
}

} // namespace retroprism
