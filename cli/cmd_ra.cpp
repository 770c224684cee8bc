// cmd_ra.cpp: `retroprism ra`, the coefficient of retroreflection R_A of a material as traffic
// standards tabulate it (ASTM E808 / E810, CIE 54.2; ASTM D4956 sheeting specifications):
// observation angles 0.2, 0.33, 0.5, 1.0, 1.5 degrees x entrance angles -4, 15, 30, 40, 45
// degrees at one rotation angle epsilon. R_A = f cos(theta_i) cos(theta_o) in cd lx^-1 m^-2
// (MODEL.md section 5); the angle conventions are written in photometry.h. With --table
// TABLE.csv (io/ra_table.h), the material's R_A at the table's entries against the measured
// values instead; with --standard NAME, against a bundled standard's minimums (standards.h).
#include <cmath>
#include <cstdio>
#include <string>

#include <OpenImageIO/argparse.h>

#include "color.h"
#include "commands.h"
#include "parse.h"
#include "photometry.h"
#include "query.h"
#include "ra_fit.h"
#include "ra_print.h"
#include "ra_table.h"
#include "standards.h"

namespace retroprism {

int cmd_ra(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism ra: coefficient of retroreflection R_A = f cos(theta_i) cos(theta_o) "
             "[cd lx^-1 m^-2] at the standard observation (0.2, 0.33, 0.5, 1.0, 1.5 deg) and "
             "entrance (-4, 15, 30, 40, 45 deg) angles, coplanar geometry (ASTM E808/E810, "
             "CIE 54.2: entrance angle beta from the normal to the illumination axis, negative on "
             "the other side of the normal; observation angle alpha from the illumination axis "
             "to the observation axis in the same plane, the observer keeping its side of the "
             "source; rotation epsilon turns the sample about its normal)")
        .usage(
            "retroprism ra [--material FILE.json | --document DOC.mtlx [--name NAME]] "
            "[--rotation DEG] [--wavelength NM | --photopic] [--csv] [--rgb] [--table TABLE.csv | "
            "--standard NAME [--color NAME]]");
    ap.arg("--material FILE").help("node inputs as a JSON object (default: all defaults)");
    ap.arg("--document FILE").help("a MaterialX document (.mtlx) instead of --material");
    ap.arg("--name NAME").help("the material of the document (default: its first)");
    ap.arg("--rotation DEG")
        .help("rotation angle epsilon of the sample about its normal (default 0)")
        .defaultval("0");
    ap.arg("--wavelength NM")
        .help("evaluate every channel at this wavelength in nm (the material's `wavelength` "
              "input: the diffraction of prism_pitch and, with abbe_number, the index), in "
              "(0, 2000]");
    ap.arg("--photopic")
        .help("R_A as a photometer under illuminant A sees it: the luminance over 15 wavelengths "
              "410-690 nm weighted by illuminant A x V(lambda) (CIE 54.2), the material's "
              "wavelength replaced; not with --wavelength or --rgb")
        .store_true();
    ap.arg("--csv").help("CSV on standard output (Y and R, G, B per row)").store_true();
    ap.arg("--rgb").help("text: also the R, G and B tables").store_true();
    ap.arg("--table FILE")
        .help("R_A at the entries of a measured table (CSV, as fit --ra reads it): measured, "
              "the material's and the error per entry");
    ap.arg("--standard NAME")
        .help("the material against a bundled standard's minimum R_A (NAME: one of `--standard "
              "list`): per entry of its colour the minimum, the material's R_A and pass or FAIL");
    ap.arg("--color NAME").help("--standard: the material's sheeting colour (default white)");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;
    const std::string standard = ap["standard"].get<std::string>();
    const std::string color = ap["color"].get<std::string>();
    if (standard == "list") {
        print_standard_list(stdout);
        return 0;
    }
    if (!color.empty() && standard.empty()) throw InputError("--color goes with --standard NAME");

    const std::string json = ap["material"].get<std::string>();
    const std::string doc = ap["document"].get<std::string>();
    const std::string name = ap["name"].get<std::string>();
    if (!json.empty() && !doc.empty())
        throw InputError("give either --material FILE.json or --document DOC.mtlx, not both");
    if (!name.empty() && doc.empty()) throw InputError("--name selects a material of --document");
    const double rotation = parse_number(ap["rotation"].get<std::string>(), "--rotation");

    Params p;
    std::string label = "the default material";
    if (!json.empty()) {
        p = params_from_json(read_json(json), json);
        label = json;
    } else if (!doc.empty()) {
        std::string materialName;
        p = document_params(doc, name, &materialName);
        label = "material \"" + materialName + "\" of " + doc;
    }
    const std::string nm = ap["wavelength"].get<std::string>();
    if (!nm.empty()) {
        p.wavelength = parse_number(nm, "--wavelength");
        if (!(p.wavelength > 0.0 && p.wavelength <= 2000.0))
            throw InputError("--wavelength " + nm + " is outside (0, 2000] nm");
        label += " at " + nm + " nm";
    }
    const bool photopic = ap["photopic"].get<int>() != 0;
    const RaSpectrum spectrum = photopic ? RaSpectrum::Photopic : RaSpectrum::Channels;
    if (photopic) {
        if (!nm.empty()) throw InputError("give either --wavelength NM or --photopic, not both");
        if (ap["rgb"].get<int>())
            throw InputError("--rgb: the photopic R_A is one luminance, not three channels");
        label += ", photopic (illuminant A x V(lambda))";
    }
    const std::string tableFile = ap["table"].get<std::string>();
    if (!standard.empty()) {
        if (!tableFile.empty()) throw InputError("give either --table or --standard, not both");
        const StandardJudgement j =
            judge_standard(read_standard(standard), p, color.empty() ? "white" : color, spectrum);
        print_standard_judgement(standard, j, label, stdout);
        return 0;
    }
    if (!tableFile.empty()) {
        const RaMeasurements m = read_ra_table(tableFile);
        std::printf("R_A [cd lx^-1 m^-2] of %s at the entries of %s\n", label.c_str(),
                    tableFile.c_str());
        print_ra_comparison(m, {{"material", ra_node_values(p, m.entries, spectrum)}}, stdout);
        return 0;
    }
    const RaTable t =
        ra_table(p, rotation, ra_observation_angles(), ra_entrance_angles(), spectrum);
    if (ap["csv"].get<int>())
        print_ra_csv(t, stdout);
    else
        print_ra_table(t, label, ap["rgb"].get<int>() != 0, stdout);
    return 0;
}

} // namespace retroprism
