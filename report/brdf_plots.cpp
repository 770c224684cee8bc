// brdf_plots.cpp: the demo's figures (see brdf_plots.h).
#include "brdf_plots.h"

#include <algorithm>
#include <cmath>

#include <OpenImageIO/imagebufalgo.h>

#include "figure.h"
#include "parallel.h"
#include "photometry.h"

namespace retroprism::plot {

namespace {

constexpr double kDeg = M_PI / 180.0;
const char* const kLobeName[4] = {"surface", "retro", "diffuse", "total"};

std::string decade_label(double d) {
    return fmt(d == 0 ? "%.0f" : "%+.0f", d);
}

LegendEntry legend_line(const std::string& label, const Rgb& c, int width) {
    LegendEntry e;
    e.label = label;
    e.style.color = c;
    e.style.width = width;
    return e;
}

// The log10 values of the hemisphere maps: panels side by side, NaN outside the disk or where
// the value is 0.
std::vector<float> hemisphere_logs(const PrismaticRetroreflector<double>& node,
                                   const std::vector<double>& thetas, int panel) {
    const int width = int(thetas.size()) * panel;
    std::vector<float> logs(size_t(width) * size_t(panel), NAN);
    parallel_for(size_t(panel), 0, [&](size_t yi) {
        const int y = int(yi);
        const double v = 1.0 - (y + 0.5) * 2.0 / panel;
        for (size_t k = 0; k < thetas.size(); ++k) {
            const glm::dvec3 wi(std::sin(thetas[k] * kDeg), 0.0, std::cos(thetas[k] * kDeg));
            for (int x = 0; x < panel; ++x) {
                const double u = (x + 0.5) * 2.0 / panel - 1.0, r2 = u * u + v * v;
                if (r2 >= 1.0) continue;
                const glm::dvec3 wo(u, v, std::sqrt(1.0 - r2));
                const double val = luminance_709(node.eval(wi, wo).f.total()) * wo.z;
                if (val > 0 && std::isfinite(val))
                    logs[size_t(y) * size_t(width) + k * size_t(panel) + size_t(x)] =
                        float(std::log10(val));
            }
        }
    });
    return logs;
}

// Panel k of the maps through the colour map, transparent outside the disk.
OIIO::ImageBuf map_image(const OIIO::ImageBuf& colored, int k, int panel) {
    OIIO::ImageBuf out(OIIO::ImageSpec(panel, panel, 4, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::zero(out);
    for (int y = 0; y < panel; ++y)
        for (int x = 0; x < panel; ++x) {
            const double u = (x + 0.5) * 2.0 / panel - 1.0, v = 1.0 - (y + 0.5) * 2.0 / panel;
            if (u * u + v * v >= 1.0) continue;
            float c[4] = {0, 0, 0, 1};
            colored.getpixel(k * panel + x, y, c, 3);
            out.setpixel(x, y, c, 4);
        }
    return out;
}

Series circle(double r, const Rgb& c) {
    Series s;
    for (int i = 0; i <= 360; ++i) {
        s.x.push_back(r * std::cos(2 * M_PI * i / 360));
        s.y.push_back(r * std::sin(2 * M_PI * i / 360));
    }
    s.color = c;
    s.width = 1;
    return s;
}

} // namespace

void slice_layout(Figure& fig) {
    fig.title_size = 24;
    fig.panel_width = 510;
    fig.panel_height = 432;
    fig.pad_left = 60;
    fig.pad_right = 30;
    fig.top = 40;
    fig.pad_top = 64;
    fig.pad_bottom = 64;
}

Panel slice_panel(double thetaDeg, double yLo, double yHi, const std::string& angle,
                  const std::string& outgoing) {
    Panel pan;
    pan.y.log = true;
    pan.y.lo = yLo;
    pan.y.hi = yHi;
    pan.y.label = [](double d, double) { return decade_label(d); };
    pan.y.label_size = 15;
    pan.x.lo = -90;
    pan.x.hi = 90;
    pan.x.step = 30;
    pan.x.label = [](double v, double) { return fmt("%.0f", v); };
    pan.x.label_size = 15;
    pan.heading = fmt((angle + " = %.0f deg").c_str(), thetaDeg);
    pan.x_label = "signed " + outgoing + " [deg]  (+: light's side)";
    // Where the peaks are expected: mirror at -theta, retro at +theta.
    Marker retro, mirror;
    retro.x = thetaDeg;
    retro.color = kLobeColor[1];
    retro.label = "retro";
    mirror.x = -thetaDeg;
    mirror.color = kLobeColor[0];
    mirror.label = "mirror";
    mirror.label_left = true;
    pan.markers = {retro, mirror};
    return pan;
}

OIIO::ImageBuf slice_figure(const std::string& name, const std::string& inputsLine,
                            const std::vector<BrdfSlice>& slices, Text& text) {
    // Shared vertical range: whole decades, 6 of them below the highest point.
    std::vector<double> totals;
    for (const BrdfSlice& sl : slices)
        totals.insert(totals.end(), sl.y[3].begin(), sl.y[3].end());
    Figure fig;
    fig.title = name + ": in-plane slices of log10(f cos theta_o) [1/sr], luminance Y";
    fig.cols = int(slices.size());
    slice_layout(fig);
    Axis y;
    fit_log(y, totals, 6, 0.05);
    for (const BrdfSlice& sl : slices) {
        Panel pan = slice_panel(sl.thetaIDeg, y.lo, y.hi, "theta_i", "theta_o");
        // The total first and thick, the lobes thin on top of it.
        for (int l : {3, 2, 0, 1}) {
            Series s;
            s.x = sl.s;
            s.y = sl.y[l];
            s.color = kLobeColor[l];
            s.width = l == 3 ? 3 : 1;
            pan.series.push_back(s);
        }
        fig.panels.push_back(pan);
    }
    for (int l : {3, 0, 1, 2})
        fig.legend.push_back(legend_line(kLobeName[l], kLobeColor[l], l == 3 ? 3 : 2));
    fig.caption = {"theta_o > 0: wo on the light's side of the normal (phi_o = phi_i = 0), so the "
                   "retro peak sits at theta_o = +theta_i and the mirror peak at theta_o = "
                   "-theta_i. Curves: Rec.709 luminance Y of f cos theta_o per lobe; values below "
                   "the axis are cut off.",
                   inputsLine};
    return render(fig, text);
}

OIIO::ImageBuf hemisphere_figure(const std::string& name,
                                 const PrismaticRetroreflector<double>& node,
                                 const std::vector<double>& thetas, int panel, Text& text) {
    namespace IBA = OIIO::ImageBufAlgo;
    const std::vector<float> logs = hemisphere_logs(node, thetas, panel);
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
    std::vector<float> normalized(logs.size(), 0.0f);
    for (size_t i = 0; i < logs.size(); ++i)
        if (std::isfinite(logs[i]))
            normalized[i] = float(std::clamp((logs[i] - lo) / (hi - lo), 0.0, 1.0));
    const int width = int(thetas.size()) * panel;
    OIIO::ImageBuf t(OIIO::ImageSpec(width, panel, 1, OIIO::TypeDesc::FLOAT));
    t.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, normalized.data());
    const OIIO::ImageBuf colored = IBA::color_map(t, 0, "inferno");

    Figure fig;
    fig.title =
        name + ": log10 of the total f cos theta_o [1/sr] (luminance Y) over the hemisphere";
    fig.cols = int(thetas.size());
    fig.panel_width = fig.panel_height = panel;
    fig.pad_left = 0;
    fig.pad_right = 40;
    fig.top = 40;
    fig.pad_top = 70;
    fig.pad_bottom = 10;
    for (size_t k = 0; k < thetas.size(); ++k) {
        Panel pan;
        pan.frame = false;
        pan.x.lo = pan.y.lo = -1;
        pan.x.hi = pan.y.hi = 1;
        pan.image = map_image(colored, int(k), panel);
        // Disk outline and the 30 and 60 degree circles.
        pan.series = {circle(1.0, kAxis), circle(std::sin(30 * kDeg), kRing),
                      circle(std::sin(60 * kDeg), kRing)};
        pan.heading = fmt("theta_i = %.0f deg", thetas[k]);
        Note px, py;
        px.x = 1.02;
        px.text = "+x";
        px.ay = OIIO::ImageBufAlgo::TextAlignY::Center;
        py.y = 1.03;
        py.text = "+y";
        py.ax = OIIO::ImageBufAlgo::TextAlignX::Center;
        pan.notes = {px, py};
        fig.panels.push_back(std::move(pan));
    }
    fig.color_bar = ColorBar{"inferno", lo, hi, decade_label};
    fig.caption = {"Orthographic view from above (+z): pixel (u, v) -> wo = (u, v, sqrt(1 - u^2 - "
                   "v^2)); the light is toward +x (phi_i = 0).",
                   "Retro peak at the light's direction (right of centre), mirror peak opposite "
                   "it; grey rings at theta_o = 30 and 60 deg."};
    return render(fig, text);
}

} // namespace retroprism::plot
