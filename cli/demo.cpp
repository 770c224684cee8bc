// demo.cpp: `retroprism demo`, pictures of the bundled example materials.
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

#include "commands.h"
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
// Rec. 709 luminance weights: the plots show photometric Y of the RGB values.
constexpr double kLumR = 0.2126, kLumG = 0.7152, kLumB = 0.0722;

struct Material {
    std::string name; // file stem
    std::string path;
    Params params;
    json inputs; // as read from the file
};

double luminance(const vec3& c) {
    return kLumR * c.x + kLumG * c.y + kLumB * c.z;
}

vec3 incident(double thetaIDeg) {
    return vec3(std::sin(thetaIDeg * kDeg), 0.0, std::cos(thetaIDeg * kDeg));
}

// Counts values that should never come out of the node (NaN, Inf, negative), with one example.
struct Anomalies {
    std::atomic<long> count{0};
    std::string example;
    void check(const Node::Lobes& f, const vec3& wi, const vec3& wo) {
        const vec3 v[3] = {f.surface, f.retro, f.diffuse};
        const char* names[3] = {"surface", "retro", "diffuse"};
        for (int l = 0; l < 3; ++l)
            for (int c = 0; c < 3; ++c)
                if (!std::isfinite(v[l][c]) || v[l][c] < 0) {
                    if (++count == 1) {
                        char buf[256];
                        std::snprintf(
                            buf, sizeof buf,
                            "%s[%d] = %g at wi = (%.6f, %.6f, %.6f), wo = (%.6f, %.6f, %.6f)",
                            names[l], c, v[l][c], wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
                        example = buf;
                    }
                }
    }
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

// Hemisphere maps: kPanels panels of n x n pixels side by side, 12 channels per pixel
// (surface, retro, diffuse, total; RGB), value f cos(theta_o) at the pixel centre.
std::vector<float> hemisphere_maps(const Node& node, int n, Anomalies& anomalies) {
    const int width = kPanels * n, nch = 12;
    std::vector<float> data(size_t(width) * n * nch, 0.0f);
    OIIO::parallel_for(0, n, [&](int32_t y) {
        const double v = 1.0 - (y + 0.5) * 2.0 / n;
        for (int k = 0; k < kPanels; ++k) {
            const vec3 wi = incident(kThetaIDeg[k]);
            for (int x = 0; x < n; ++x) {
                const double u = (x + 0.5) * 2.0 / n - 1.0;
                const double r2 = u * u + v * v;
                if (r2 >= 1.0) continue;
                const vec3 wo(u, v, std::sqrt(1.0 - r2));
                const Node::Eval e = node.eval(wi, wo);
                anomalies.check(e.f, wi, wo);
                const vec3 lobes[4] = {e.f.surface, e.f.retro, e.f.diffuse, e.f.total()};
                float* px = &data[(size_t(y) * width + size_t(k) * n + x) * nch];
                for (int l = 0; l < 4; ++l)
                    for (int c = 0; c < 3; ++c)
                        px[3 * l + c] = float(lobes[l][c] * wo.z);
            }
        }
    });
    return data;
}

// One in-plane slice: the luminance of f cos(theta_o) per lobe at signed angles s (degrees),
// wo = (sin s, 0, cos s), so s > 0 is on the light's side of the normal.
struct Slice {
    double thetaIDeg = 0;
    std::vector<double> s;
    std::vector<double> y[4]; // surface, retro, diffuse, total
};

// Uniform samples plus geometric refinement toward the retro (+theta_i) and mirror
// (-theta_i) peaks, which can be far narrower than the uniform step at low roughness.
std::vector<double> slice_angles(double thetaIDeg) {
    std::vector<double> s;
    for (int i = 0; i <= kSliceSamples; ++i)
        s.push_back(-90.0 + 180.0 * i / kSliceSamples);
    for (double peak : {thetaIDeg, -thetaIDeg}) {
        s.push_back(peak);
        for (double d = 1e-4; d < 3.0; d *= 1.25) {
            s.push_back(peak - d);
            s.push_back(peak + d);
        }
    }
    std::sort(s.begin(), s.end());
    s.erase(std::remove_if(s.begin(), s.end(), [](double a) { return a < -90.0 || a > 90.0; }),
            s.end());
    s.erase(std::unique(s.begin(), s.end()), s.end());
    return s;
}

Slice slice(const Node& node, double thetaIDeg, Anomalies& anomalies) {
    Slice sl;
    sl.thetaIDeg = thetaIDeg;
    sl.s = slice_angles(thetaIDeg);
    for (auto& v : sl.y)
        v.assign(sl.s.size(), 0.0);
    const vec3 wi = incident(thetaIDeg);
    OIIO::parallel_for(0, int32_t(sl.s.size()), [&](int32_t i) {
        const double a = sl.s[size_t(i)] * kDeg;
        const vec3 wo(std::sin(a), 0.0, std::cos(a));
        const Node::Eval e = node.eval(wi, wo);
        anomalies.check(e.f, wi, wo);
        const double c = std::max(wo.z, 0.0);
        sl.y[0][size_t(i)] = luminance(e.f.surface) * c;
        sl.y[1][size_t(i)] = luminance(e.f.retro) * c;
        sl.y[2][size_t(i)] = luminance(e.f.diffuse) * c;
        sl.y[3][size_t(i)] = luminance(e.f.total()) * c;
    });
    return sl;
}

// ---------------------------------------------------------------------------------------------
// Drawing.

using namespace plot;
const char* kLobeName[4] = {"surface", "retro", "diffuse", "total"};

// The slice plots of one material: one panel per theta_i, shared log axis.
OIIO::ImageBuf slice_plot(const Material& mat, const std::vector<Slice>& slices, Text& text) {
    namespace IBA = OIIO::ImageBufAlgo;
    const int panelW = 600, W = 30 + kPanels * panelW, H = 680;
    OIIO::ImageBuf img(OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT));
    IBA::fill(img, kBackground);

    // Shared vertical range: whole decades, 6 of them below the highest point.
    double top = -1e300;
    for (const Slice& sl : slices)
        for (double v : sl.y[3])
            if (v > 0 && std::isfinite(v)) top = std::max(top, std::log10(v));
    const double yMax = top > -1e300 ? std::ceil(top + 0.05) : 1.0, yMin = yMax - 6.0;

    text.draw(img, 30, 36,
              mat.name + ": in-plane slices of log10(f cos theta_o) [1/sr], luminance Y", 24,
              kText);
    for (int k = 0; k < int(slices.size()); ++k) {
        const Slice& sl = slices[size_t(k)];
        const int left = 30 + k * panelW + 60, right = left + panelW - 90, topY = 104, bottom = 536;
        auto X = [&](double s) {
            return int(std::lround(left + (s + 90.0) / 180.0 * (right - left)));
        };
        auto Y = [&](double ly) {
            return int(std::lround(bottom - (ly - yMin) / (yMax - yMin) * (bottom - topY)));
        };
        const OIIO::ROI clip(left, right + 1, topY, bottom + 1);
        IBA::render_box(img, left, topY, right, bottom, kPlotBackground, true);
        for (int d = int(yMin); d <= int(yMax); ++d) {
            IBA::render_line(img, left, Y(d), right, Y(d), kGrid);
            text.draw(img, left - 8, Y(d), fmt(d == 0 ? "%.0f" : "%+.0f", d), 15, kDimText,
                      IBA::TextAlignX::Right, IBA::TextAlignY::Center);
        }
        for (int a = -90; a <= 90; a += 30) {
            IBA::render_line(img, X(a), topY, X(a), bottom, kGrid);
            text.draw(img, X(a), bottom + 20, fmt("%.0f", a), 15, kDimText,
                      IBA::TextAlignX::Center);
        }
        // Where the peaks are expected: mirror at -theta_i, retro at +theta_i.
        dashed_vline(img, X(sl.thetaIDeg), topY, bottom, kLobeColor[1]);
        dashed_vline(img, X(-sl.thetaIDeg), topY, bottom, kLobeColor[0]);
        text.draw(img, X(sl.thetaIDeg) + 4, topY - 6, "retro", 14, kLobeColor[1]);
        text.draw(img, X(-sl.thetaIDeg) - 4, topY - 6, "mirror", 14, kLobeColor[0],
                  IBA::TextAlignX::Right);
        IBA::render_box(img, left, topY, right, bottom, kAxis);
        text.draw(img, (left + right) / 2, topY - 30, fmt("theta_i = %.0f deg", sl.thetaIDeg), 20,
                  kText, IBA::TextAlignX::Center);
        text.draw(img, (left + right) / 2, bottom + 44, "signed theta_o [deg]  (+: light's side)",
                  15, kDimText, IBA::TextAlignX::Center);

        // Curves: the total first and thick, the lobes thin on top of it. Points below the
        // axis are pulled to just below it, so a curve plunges out of view instead of vanishing.
        for (int l : {3, 2, 0, 1}) {
            const double floorY = yMin - 0.5;
            int px = 0, py = 0;
            bool have = false, prevBelow = true;
            for (size_t i = 0; i < sl.s.size(); ++i) {
                const double v = sl.y[l][i];
                const double ly =
                    (v > 0 && std::isfinite(v)) ? std::max(std::log10(v), floorY) : floorY;
                const bool below = ly < yMin;
                const int x = X(sl.s[i]), y = Y(ly);
                if (have && !(below && prevBelow) && (x != px || y != py))
                    thick_line(img, px, py, x, y, kLobeColor[l], l == 3 ? 3 : 1, clip);
                if (!have || x != px || y != py) {
                    px = x;
                    py = y;
                }
                have = true;
                prevBelow = below;
            }
        }
    }
    // Legend and caption.
    int lx = 90;
    const int ly = 600;
    for (int l : {3, 0, 1, 2}) {
        thick_line(img, lx, ly, lx + 36, ly, kLobeColor[l], l == 3 ? 3 : 2, OIIO::ROI::All());
        text.draw(img, lx + 44, ly, kLobeName[l], 17, kText, IBA::TextAlignX::Left,
                  IBA::TextAlignY::Center);
        lx += 150;
    }
    text.draw(img, 30, 640,
              "theta_o > 0: wo on the light's side of the normal (phi_o = phi_i = 0), so the retro "
              "peak sits at "
              "theta_o = +theta_i and the mirror peak at theta_o = -theta_i. Curves: Rec.709 "
              "luminance Y of f cos theta_o per "
              "lobe; values below the axis are cut off.",
              14, kDimText);
    text.draw(img, 30, 662, "Inputs: " + mat.inputs.dump() + "   (" + mat.path + ")", 13, kDimText);
    return img;
}

// False-colour map of log10 Y(total f cos theta_o), evaluated on its own grid of `panel`
// pixels per side (finer than the EXR: the node is cheap and the peaks are small).
OIIO::ImageBuf hemisphere_png(const Material& mat, const Node& node, int panel, Text& text) {
    namespace IBA = OIIO::ImageBufAlgo;
    const int gap = 40, left = 30, topY = 110;
    const int W = left + kPanels * (panel + gap) + 110, H = topY + panel + 110;
    OIIO::ImageBuf img(OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT));
    IBA::fill(img, kBackground);

    // log10 Y of the total, NaN outside the disk or where the value is 0.
    const int width = kPanels * panel;
    std::vector<float> logs(size_t(width) * panel, NAN);
    OIIO::parallel_for(0, panel, [&](int32_t y) {
        const double v = 1.0 - (y + 0.5) * 2.0 / panel;
        for (int k = 0; k < kPanels; ++k) {
            const vec3 wi = incident(kThetaIDeg[k]);
            for (int x = 0; x < panel; ++x) {
                const double u = (x + 0.5) * 2.0 / panel - 1.0, r2 = u * u + v * v;
                if (r2 >= 1.0) continue;
                const vec3 wo(u, v, std::sqrt(1.0 - r2));
                const double val = luminance(node.eval(wi, wo).f.total()) * wo.z;
                if (val > 0 && std::isfinite(val))
                    logs[size_t(y) * width + size_t(k) * panel + x] = float(std::log10(val));
            }
        }
    });
    // Range: from the highest value down to the 5th percentile of the disk (whole decades,
    // 2 to 6 of them), so the diffuse floor is visible whatever its level.
    std::vector<float> finite;
    for (float l : logs)
        if (std::isfinite(l)) finite.push_back(l);
    double hi = 1.0, lo = -1.0;
    if (!finite.empty()) {
        auto p5 = finite.begin() + std::ptrdiff_t(finite.size() / 20);
        std::nth_element(finite.begin(), p5, finite.end());
        hi = std::ceil(*std::max_element(finite.begin(), finite.end()));
        lo = std::clamp(std::floor(double(*p5)), hi - 6.0, hi - 2.0);
    }

    // Normalised log values through a colour map; the disk is where r^2 < 1.
    std::vector<float> normalized(logs.size(), 0.0f);
    for (size_t i = 0; i < logs.size(); ++i)
        if (std::isfinite(logs[i]))
            normalized[i] = float(std::clamp((logs[i] - lo) / (hi - lo), 0.0, 1.0));
    OIIO::ImageBuf t(OIIO::ImageSpec(width, panel, 1, OIIO::TypeDesc::FLOAT));
    t.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, normalized.data());
    auto inside = [&](int x, int y) {
        const double u = (x + 0.5) * 2.0 / panel - 1.0, v = 1.0 - (y + 0.5) * 2.0 / panel;
        return u * u + v * v < 1.0;
    };
    OIIO::ImageBuf colored = IBA::color_map(t, 0, "inferno");
    for (int k = 0; k < kPanels; ++k) {
        const int ox = left + k * (panel + gap);
        for (int y = 0; y < panel; ++y)
            for (int x = 0; x < panel; ++x) {
                if (!inside(x, y)) continue;
                float c[3];
                colored.getpixel(k * panel + x, y, c, 3);
                img.setpixel(ox + x, topY + y, c, 3);
            }
        // Disk outline, the plane of incidence and the 30/60 degree circles.
        const int cx = ox + panel / 2, cy = topY + panel / 2, R = panel / 2;
        for (double ring : {1.0, std::sin(30 * kDeg), std::sin(60 * kDeg)}) {
            const int steps = 360;
            for (int i = 0; i < steps; ++i) {
                const double a0 = 2 * M_PI * i / steps, a1 = 2 * M_PI * (i + 1) / steps;
                IBA::render_line(
                    img, int(cx + ring * R * std::cos(a0)), int(cy + ring * R * std::sin(a0)),
                    int(cx + ring * R * std::cos(a1)), int(cy + ring * R * std::sin(a1)),
                    ring == 1.0 ? kAxis : Rgb{0.45f, 0.45f, 0.5f});
            }
        }
        text.draw(img, cx, topY - 36, fmt("theta_i = %.0f deg", kThetaIDeg[k]), 20, kText,
                  IBA::TextAlignX::Center);
        text.draw(img, cx + R + 4, cy, "+x", 14, kDimText, IBA::TextAlignX::Left,
                  IBA::TextAlignY::Center);
        text.draw(img, cx, topY - 8, "+y", 14, kDimText, IBA::TextAlignX::Center);
    }
    // Colour bar.
    const int bx = left + kPanels * (panel + gap) + 4, bw = 22;
    OIIO::ImageBuf ramp(OIIO::ImageSpec(1, panel, 1, OIIO::TypeDesc::FLOAT));
    for (int y = 0; y < panel; ++y) {
        const float tv = 1.0f - float(y) / float(panel - 1);
        ramp.setpixel(0, y, &tv);
    }
    const OIIO::ImageBuf rampColored = IBA::color_map(ramp, 0, "inferno");
    for (int y = 0; y < panel; ++y) {
        float c[3];
        rampColored.getpixel(0, y, c, 3);
        IBA::render_line(img, bx, topY + y, bx + bw, topY + y, Rgb{c[0], c[1], c[2]});
    }
    IBA::render_box(img, bx, topY, bx + bw, topY + panel - 1, kAxis);
    for (int d = int(lo); d <= int(hi); ++d) {
        const int y = topY + int(std::lround((hi - d) / (hi - lo) * (panel - 1)));
        IBA::render_line(img, bx + bw, y, bx + bw + 5, y, kAxis);
        text.draw(img, bx + bw + 9, y, fmt(d == 0 ? "%.0f" : "%+.0f", d), 15, kDimText,
                  IBA::TextAlignX::Left, IBA::TextAlignY::Center);
    }
    text.draw(img, left, 34,
              mat.name +
                  ": log10 of the total f cos theta_o [1/sr] (luminance Y) over the hemisphere",
              22, kText);
    text.draw(img, left, topY + panel + 40,
              "Orthographic view from above (+z): pixel (u, v) -> wo = (u, v, sqrt(1 - u^2 - "
              "v^2)); the light is "
              "toward +x (phi_i = 0).",
              14, kDimText);
    text.draw(img, left, topY + panel + 62,
              "Retro peak at the light's direction (right of centre), mirror peak opposite it; "
              "grey rings at theta_o = "
              "30 and 60 deg.",
              14, kDimText);
    return img;
}

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

    Text text("retroprism demo");
    long anomalyTotal = 0;
    for (const Material& mat : materials) {
        const Node node(mat.params);
        Anomalies anomalies;
        const std::vector<float> maps = hemisphere_maps(node, kMapSize, anomalies);
        std::vector<Slice> slices;
        for (double t : kThetaIDeg)
            slices.push_back(slice(node, t, anomalies));

        OIIO::ImageBuf exr = exr_image(mat, maps, kMapSize);
        OIIO::ImageBuf plot = slice_plot(mat, slices, text);
        OIIO::ImageBuf hemi = hemisphere_png(mat, node, kPngMapSize, text);
        const std::vector<std::pair<fs::path, OIIO::ImageBuf*>> files = {
            {out / (mat.name + ".exr"), &exr},
            {out / (mat.name + "_slices.png"), &plot},
            {out / (mat.name + "_hemisphere.png"), &hemi}};
        const char* formats[] = {"openexr", "png", "png"};
        write_all(files, formats);
        for (const auto& f : files)
            std::printf("wrote %s\n", f.first.string().c_str());

        // Summary: the retro peak f(wi, wi) and the diffuse floor f_d(wi, n), luminance Y.
        std::string peaks, floors;
        for (double t : kThetaIDeg) {
            const vec3 wi = incident(t);
            const Node::Eval e = node.eval(wi, wi), en = node.eval(wi, vec3(0, 0, 1));
            peaks += (peaks.empty() ? "" : " / ") + fmt("%.4g", luminance(e.f.total()));
            floors += (floors.empty() ? "" : " / ") + fmt("%.3g", luminance(en.f.diffuse));
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
