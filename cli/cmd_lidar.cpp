// cmd_lidar.cpp: `retroprism lidar`: the return of a LiDAR from flat targets of given materials
// (analysis/lidar.h: geometry, radiometry, assumptions), against range, entrance angle and
// wavelength, beside a Lambertian target of the same albedo; a table, CSV and a figure.
#include <cstdio>
#include <string>
#include <vector>

#include <OpenImageIO/argparse.h>

#include "commands.h"
#include "error.h"
#include "figure.h"
#include "lidar.h"
#include "lidar_report.h"
#include "parse.h"

namespace retroprism {

int cmd_lidar(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro("retroprism lidar: the fraction of a LiDAR's emitted power returned by a flat target "
             "of each material (the BRDF at the wavelength integrated over the receiver's "
             "aperture and the beam's footprint), beside a Lambertian target of the same albedo. "
             "Sensor frame: emitter at the origin, beam along +z, y up; the target's centre on the "
             "beam at the range, turned by the entrance angle about y (analysis/lidar.h)")
        .usage("retroprism lidar [[LABEL=]FILE.json|DOC.mtlx ...] [--wavelength NM,...] "
               "[--range M,...] [--entrance DEG,...] [--offset X,Y,Z] [--divergence MRAD] "
               "[--aperture M] [--size W,H] [--rotation DEG] [--channel r|g|b] "
               "[--baseline TABLE.csv] [--csv] [--plot OUT.png]");
    std::vector<std::string> files;
    ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> a) { files.push_back(a[0]); });
    ap.arg("--wavelength NM")
        .help("wavelengths in nm, comma-separated (default 905)")
        .defaultval("905");
    ap.arg("--range M").help("ranges in m, comma-separated (default 20)").defaultval("20");
    ap.arg("--entrance DEG")
        .help("entrance angles in degrees, comma-separated (default 0)")
        .defaultval("0");
    ap.arg("--offset X,Y,Z")
        .help("the receiver aperture's centre from the emitter in m (default 0.03,0,0)")
        .defaultval("0.03,0,0");
    ap.arg("--divergence MRAD")
        .help("the beam's full divergence at its 1/e^2 irradiance in mrad (default 3)")
        .defaultval("3");
    ap.arg("--aperture M")
        .help("the receiver aperture's diameter in m (default 0.025)")
        .defaultval("0.025");
    ap.arg("--size W,H")
        .help("the target's width and height in m (default 0,0: larger than the footprint)")
        .defaultval("0,0");
    ap.arg("--rotation DEG")
        .help("rotation angle of the material about the target's normal (default 0)")
        .defaultval("0");
    ap.arg("--channel C")
        .help("the material's colour channel r, g or b (default r, the nearest the infrared)")
        .defaultval("r");
    ap.arg("--baseline TABLE.csv")
        .help("also the MaterialX-style retroreflective GGX fitted to this R_A table (as fit --ra "
              "fits it) at the same geometries, beside each material");
    ap.arg("--csv").help("CSV on standard output, a row per geometry").store_true();
    ap.arg("--plot FILE").help("write the figure (PNG): P_r/P against range");
    int status = 0;
    if (!parse_command_args(ap, argc, argv, status)) return status;

    if (!ap["baseline"].get<std::string>().empty() && ap["csv"].get<int>())
        throw InputError("--baseline prints a text table beside the materials': not with --csv");
    std::vector<LidarMaterial> materials;
    for (const std::string& f : files)
        materials.push_back(lidar_material(f));
    if (materials.empty()) materials.push_back({"default material", Params()});
    LidarSensor sensor;
    const std::vector<double> offset =
        parse_number_list(ap["offset"].get<std::string>(), "--offset");
    if (offset.size() != 3) throw InputError("--offset: expected X,Y,Z in m");
    sensor.receiver_offset = glm::dvec3(offset[0], offset[1], offset[2]);
    sensor.divergence_mrad = parse_number(ap["divergence"].get<std::string>(), "--divergence");
    sensor.aperture_m = parse_number(ap["aperture"].get<std::string>(), "--aperture");
    LidarTarget target;
    const std::vector<double> size = parse_number_list(ap["size"].get<std::string>(), "--size");
    if (size.size() != 2) throw InputError("--size: expected W,H in m");
    target.width_m = size[0];
    target.height_m = size[1];
    target.rotation_deg = parse_number(ap["rotation"].get<std::string>(), "--rotation");
    const std::string channel = ap["channel"].get<std::string>();
    const int c = channel == "r" ? 0 : channel == "g" ? 1 : channel == "b" ? 2 : -1;
    if (c < 0) throw InputError("--channel " + channel + ": expected r, g or b");
    const std::vector<LidarRow> rows =
        lidar_sweep(materials, sensor, target,
                    parse_number_list(ap["wavelength"].get<std::string>(), "--wavelength"),
                    parse_number_list(ap["range"].get<std::string>(), "--range"),
                    parse_number_list(ap["entrance"].get<std::string>(), "--entrance"), c);

    const std::string setup =
        "receiver offset (" + plot::fmt("%g", offset[0]) + plot::fmt(", %g", offset[1]) +
        plot::fmt(", %g) m", offset[2]) + plot::fmt(", aperture %g m", sensor.aperture_m) +
        plot::fmt(", divergence %g mrad (1/e^2, full)", sensor.divergence_mrad) +
        (target.width_m > 0
             ? plot::fmt(", target %g", target.width_m) + plot::fmt(" x %g m", target.height_m)
             : std::string(", target larger than the footprint")) +
        plot::fmt(", rotation %g deg", target.rotation_deg) + ", channel " + channel;
    if (ap["csv"].get<int>()) {
        print_lidar_csv(rows, stdout);
    } else {
        std::printf("LiDAR return: %s\n\n", setup.c_str());
        print_lidar_table(rows, stdout);
    }
    const std::string baseline = ap["baseline"].get<std::string>();
    if (!baseline.empty()) {
        const std::vector<LidarReturn> ggx =
            lidar_returns_at(lidar_ggx_brdf(baseline, c), rows, sensor, target);
        print_lidar_model(rows, ggx, "the GGX fitted to " + baseline, stdout);
    }
    const std::string plotFile = ap["plot"].get<std::string>();
    if (!plotFile.empty()) {
        plot::Text text("retroprism lidar");
        plot::write_png(plot::lidar_figure("LiDAR return against range", rows, {setup}, text),
                        plotFile);
        std::fprintf(stderr, "wrote %s\n", plotFile.c_str());
    }
    return 0;
}

} // namespace retroprism
