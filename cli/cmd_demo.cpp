// cmd_demo.cpp: `retroprism demo`, pictures of the bundled example materials.
//
// For each material (a JSON object of node inputs) and incidence angles theta_i = 5, 30, 60
// degrees (phi_i = 0, wi toward +x), evaluated in double:
//   NAME.exr             hemisphere maps of f cos(theta_o) [1/sr] per lobe and total (layers
//                        surface, retro, diffuse, total; R, G, B), one 256x256 panel per
//                        theta_i side by side: orthographic view from +z, pixel (u, v) of the
//                        unit disk -> wo = (u, v, sqrt(1 - u^2 - v^2)), u right, v up; 0 outside.
//   NAME_slices.png      log10 of the luminance Y of f cos(theta_o) in the plane of incidence
//                        against the signed outgoing angle (> 0: wo on the light's side).
//   NAME_hemisphere.png  log10 of the luminance of the total, false colour, 512 px per panel.
// All materials are read and checked before anything is written; each material's files are
// written under temporary names and renamed once all of them are complete.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/argparse.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/parallel.h>

#include "brdf_maps.h"
#include "brdf_plots.h"
#include "commands.h"
#include "photometry.h"
#include "plot.h"
#include "query.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace retroprism {
namespace {

using Node = PrismaticRetroreflector<double>;
using vec3 = Node::vec3;

constexpr double kThetaIDeg[3] = {5.0, 30.0, 60.0};
constexpr int kPanels = 3;
constexpr int kMapSize = 256;       // EXR hemisphere panel, pixels per side
constexpr int kPngMapSize = 512;    // false-colour PNG panel, pixels per side
constexpr int kSliceSamples = 4000; // uniform samples of the signed theta_o in [-90, 90]
constexpr double kDeg = M_PI / 180.0;

struct Material {
    std::string name; // file stem
    std::string path;
    Params params;
    json inputs; // as read from the file
};

// ---------------------------------------------------------------------------------------------
// Locating and reading the materials.

bool is_dir(const fs::path& p) {
    std::error_code ec;
    return fs::is_directory(p, ec);
}

// examples/materials in the first ancestor of `start` (itself included) that has one.
fs::path find_upward(fs::path start) {
    std::error_code ec;
    start = fs::weakly_canonical(start, ec);
    if (ec) return {};
    for (fs::path p = start;; p = p.parent_path()) {
        fs::path candidate = p / "examples" / "materials";
        if (is_dir(candidate)) return candidate;
        if (p == p.parent_path()) break;
    }
    return {};
}

fs::path locate_materials(const std::string& option) {
    if (!option.empty()) {
        std::error_code ec;
        if (!fs::exists(option, ec))
            throw InputError("--materials " + option + ": no such file or folder");
        return option;
    }
    std::error_code ec;
    fs::path found = find_upward(fs::current_path(ec));
    if (found.empty()) {
        fs::path exe = fs::read_symlink("/proc/self/exe", ec);
        if (!ec) found = find_upward(exe.parent_path());
    }
    if (found.empty())
        throw InputError("cannot find the folder examples/materials above the current folder or "
                         "the executable's folder; give it with --materials DIR");
    return found;
}

// Reads and checks every material; on any error prints all of them and returns false.
bool read_materials(const fs::path& where, std::vector<Material>& out) {
    std::vector<fs::path> files;
    if (is_dir(where)) {
        for (const fs::directory_entry& e : fs::directory_iterator(where))
            if (e.path().extension() == ".json" && !e.is_directory()) files.push_back(e.path());
        std::sort(files.begin(), files.end());
        if (files.empty())
            throw InputError(where.string() + ": no *.json material files in this folder");
    } else {
        files.push_back(where);
    }
    bool ok = true;
    for (const fs::path& f : files) {
        try {
            Material m;
            m.path = f.string();
            m.name = f.stem().string();
            m.inputs = read_json(m.path);
            m.params = params_from_json(m.inputs, m.path);
            out.push_back(std::move(m));
        } catch (const InputError& e) {
            std::fprintf(stderr, "retroprism demo: error: %s\n", e.what());
            ok = false;
        }
    }
    return ok;
}

// ---------------------------------------------------------------------------------------------
// Evaluation.

// ---------------------------------------------------------------------------------------------
// Writing.

OIIO::ImageBuf exr_image(const Material& mat, const std::vector<float>& maps, int n) {
    OIIO::ImageSpec spec(kPanels * n, n, 12, OIIO::TypeDesc::FLOAT);
    spec.channelnames.clear();
    for (const char* lobe : {"surface", "retro", "diffuse", "total"})
        for (const char* c : {"R", "G", "B"})
            spec.channelnames.push_back(std::string(lobe) + "." + c);
    spec.attribute("compression", "zip");
    spec.attribute("retroprism:quantity", "f cos theta_o [1/sr]");
    spec.attribute(
        "retroprism:projection",
        "orthographic view of the upper hemisphere from +z, one square panel per theta_i "
        "side by side: pixel centre (u, v) in the unit disk (u right, v up) -> wo = (u, v, "
        "sqrt(1 - u^2 - v^2)); pixels outside the disk are 0");
    spec.attribute("retroprism:incidence",
                   "wi = (sin theta_i, 0, cos theta_i), phi_i = 0 (toward +u)");
    float thetas[kPanels];
    for (int k = 0; k < kPanels; ++k)
        thetas[k] = float(kThetaIDeg[k]);
    spec.attribute("retroprism:theta_i_deg", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, kPanels),
                   thetas);
    spec.attribute("retroprism:material_file", mat.path);
    spec.attribute("retroprism:material", mat.inputs.dump());
    spec.attribute("retroprism:inputs", params_to_json(mat.params).dump());
    spec.attribute("ImageDescription",
                   "retroprism demo: prismatic retroreflector BRDF (Guo, Guo & Pan "
                   "2018), per-lobe f cos theta_o of material " +
                       mat.name);
    OIIO::ImageBuf img(spec);
    img.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, maps.data());
    return img;
}

// Writes all images under temporary names, then renames them; on failure removes them all.
void write_all(const std::vector<std::pair<fs::path, OIIO::ImageBuf*>>& files,
               const char* const* formats) {
    std::vector<fs::path> temps;
    auto cleanup = [&] {
        std::error_code ec;
        for (const fs::path& t : temps)
            fs::remove(t, ec);
    };
    for (size_t i = 0; i < files.size(); ++i) {
        const fs::path& dst = files[i].first;
        fs::path tmp =
            dst.parent_path() / ("." + dst.filename().string() + ".tmp" + std::to_string(getpid()));
        temps.push_back(tmp);
        OIIO::ImageBuf& img = *files[i].second;
        const bool png = std::string(formats[i]) == "png";
        if (!img.write(tmp.string(), png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT,
                       formats[i])) {
            std::string err = img.geterror();
            cleanup();
            throw InputError(dst.string() + ": cannot write (" + err + ")");
        }
    }
    for (size_t i = 0; i < files.size(); ++i) {
        std::error_code ec;
        fs::rename(temps[i], files[i].first, ec);
        if (ec) {
            // No partial set: also remove this material's files already in place.
            std::error_code ignored;
            for (size_t j = 0; j < i; ++j)
                fs::remove(files[j].first, ignored);
            cleanup();
            throw InputError(files[i].first.string() + ": cannot write (" + ec.message() + ")");
        }
    }
}

void prepare_out(const fs::path& out) {
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec || !is_dir(out))
        throw InputError(
            "--out " + out.string() + ": cannot create the folder" +
            (ec ? " (" + ec.message() + ")" : std::string(" (a file of that name exists)")));
    const fs::path probe = out / (".retroprism-write-test" + std::to_string(getpid()));
    {
        std::ofstream f(probe);
        if (!f || !(f << "x") || (f.close(), !f)) {
            fs::remove(probe, ec);
            throw InputError("--out " + out.string() + ": the folder is not writable");
        }
    }
    fs::remove(probe, ec);
}

} // namespace

int cmd_demo(int argc, const char** argv) {
    OIIO::ArgParse ap;
    ap.intro(
          "retroprism demo: pictures of the example materials (hemisphere EXR of f cos theta_o per "
          "lobe, in-plane slice plots and a false-colour hemisphere PNG), at theta_i = 5, 30, 60 "
          "deg")
        .usage("retroprism demo [--out DIR] [--materials DIR|FILE.json]");
    ap.arg("--out DIR")
        .help("output folder, created if missing (default out/demo)")
        .defaultval("out/demo");
    ap.arg("--materials DIR")
        .help("folder of material JSON files (every *.json), or one file (default: "
              "examples/materials "
              "found above the current folder or the executable)");
    ap.exit_on_error(false);
    if (ap.parse_args(argc, argv) < 0) {
        std::fprintf(stderr, "retroprism demo: %s\n", ap.geterror().c_str());
        return 2;
    }
    if (ap.aborted() || ap["help"].get<int>()) return 0;

    const auto t0 = std::chrono::steady_clock::now();
    const fs::path where = locate_materials(ap["materials"].get<std::string>());
    std::vector<Material> materials;
    if (!read_materials(where, materials)) {
        std::fprintf(stderr, "retroprism demo: nothing written; fix the material files above\n");
        return 1;
    }
    const fs::path out = ap["out"].get<std::string>();
    prepare_out(out);
    std::printf("materials: %s (%zu)\n", where.string().c_str(), materials.size());

    plot::Text text("retroprism demo");
    long anomalyTotal = 0;
    for (const Material& mat : materials) {
        const Node node(mat.params);
        Anomalies anomalies;
        const std::vector<double> thetaI(std::begin(kThetaIDeg), std::end(kThetaIDeg));
        const std::vector<float> maps = hemisphere_maps(node, thetaI, kMapSize, anomalies);
        std::vector<BrdfSlice> slices;
        for (double t : kThetaIDeg)
            slices.push_back(brdf_slice(node, t, kSliceSamples, anomalies));

        OIIO::ImageBuf exr = exr_image(mat, maps, kMapSize);
        OIIO::ImageBuf slicesImage = plot::slice_figure(
            mat.name, "Inputs: " + mat.inputs.dump() + "   (" + mat.path + ")", slices, text);
        OIIO::ImageBuf hemi = plot::hemisphere_figure(
            mat.name, node, std::vector<double>(std::begin(kThetaIDeg), std::end(kThetaIDeg)),
            kPngMapSize, text);
        const std::vector<std::pair<fs::path, OIIO::ImageBuf*>> files = {
            {out / (mat.name + ".exr"), &exr},
            {out / (mat.name + "_slices.png"), &slicesImage},
            {out / (mat.name + "_hemisphere.png"), &hemi}};
        const char* formats[] = {"openexr", "png", "png"};
        write_all(files, formats);
        for (const auto& f : files)
            std::printf("wrote %s\n", f.first.string().c_str());

        // Summary: the retro peak f(wi, wi) and the diffuse floor f_d(wi, n), luminance Y.
        std::string peaks, floors;
        for (double t : kThetaIDeg) {
            const vec3 wi(std::sin(t * kDeg), 0.0, std::cos(t * kDeg));
            const Node::Eval e = node.eval(wi, wi), en = node.eval(wi, vec3(0, 0, 1));
            peaks += (peaks.empty() ? "" : " / ") + plot::fmt("%.4g", luminance_709(e.f.total()));
            floors +=
                (floors.empty() ? "" : " / ") + plot::fmt("%.3g", luminance_709(en.f.diffuse));
        }
        std::printf(
            "%s: f(wi,wi) = %s 1/sr, diffuse f(wi,n) = %s 1/sr at theta_i = 5 / 30 / 60 deg "
            "(luminance Y)\n",
            mat.name.c_str(), peaks.c_str(), floors.c_str());
        if (anomalies.count > 0) {
            std::fprintf(stderr,
                         "retroprism demo: warning: %s: %ld NaN, infinite or negative lobe "
                         "values, e.g. %s\n",
                         mat.name.c_str(), long(anomalies.count), anomalies.example.c_str());
            anomalyTotal += anomalies.count;
        }
    }
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("done: %zu materials in %.2f s%s\n", materials.size(), secs,
                text.ok ? "" : " (plots without text: no font found)");
    if (anomalyTotal > 0)
        std::fprintf(stderr,
                     "retroprism demo: warning: the node returned %ld invalid values (see above)\n",
                     anomalyTotal);
    return 0;
}

} // namespace retroprism
