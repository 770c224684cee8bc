// fit_plot.cpp: the fit's comparison plot (see fit_plot.h).
#include "fit_plot.h"

#include <algorithm>
#include <cmath>

#include "brdf_plots.h"
#include "figure.h"

namespace retroprism::plot {

namespace {

const Rgb kMeasured = {0.92f, 0.92f, 0.95f};

Series curve(const FitSlice& sl, const std::vector<double>& v, const Rgb& c) {
    Series s;
    s.x = sl.s;
    s.y = v;
    s.color = c;
    s.width = 2;
    return s;
}

} // namespace

OIIO::ImageBuf fit_figure(const std::string& fileName, const std::vector<FitSlice>& slices,
                          Text& text) {
    // A shared vertical range over the measured values: at most 7 decades.
    double lo = 1e300, hi = -1e300;
    for (const FitSlice& sl : slices)
        for (double v : sl.mv)
            if (v > 0) {
                lo = std::min(lo, std::log10(v));
                hi = std::max(hi, std::log10(v));
            }
    if (!(hi >= lo)) lo = -3, hi = 1;
    const double yMax = std::ceil(hi + 0.05), yMin = std::max(std::floor(lo), yMax - 7.0);
    const Rgb nodeColor = kLobeColor[1], mrmColor = kLobeColor[0];
    Figure fig;
    fig.title =
        "fit of " + fileName + ": in-plane slices of BRDF x cos theta_v [1/sr], measured vs fitted";
    fig.cols = std::max<int>(1, int(slices.size()));
    slice_layout(fig);
    fig.pad_bottom = 110; // the models' errors under each panel
    for (const FitSlice& sl : slices) {
        Panel pan = slice_panel(sl.thetaDeg, yMin, yMax, "theta_l", "theta_v");
        pan.series = {curve(sl, sl.mrm, mrmColor), curve(sl, sl.node, nodeColor)};
        Series measured;
        measured.x = sl.ms;
        measured.y = sl.mv;
        measured.points = true;
        measured.width = 2;
        measured.color = kMeasured;
        pan.series.push_back(measured);
        pan.lines_below = {
            {fmt("node: rel RMS %.3g", sl.nodeRel) + fmt(", log RMS %.3g", sl.nodeLog), nodeColor},
            {fmt("mrm:  rel RMS %.3g", sl.mrmRel) + fmt(", log RMS %.3g", sl.mrmLog), mrmColor}};
        fig.panels.push_back(pan);
    }
    LegendEntry m, n, r;
    m.label = "measured (in-plane samples)";
    m.style.points = true;
    m.style.width = 3;
    m.style.color = kMeasured;
    n.label = "node fit (prismatic retroreflector)";
    n.style.width = 3;
    n.style.color = nodeColor;
    r.label = "mrm fit (MaterialX retroreflective GGX + Lambert)";
    r.style.width = 3;
    r.style.color = mrmColor;
    fig.legend = {m, n, r};
    return render(fig, text);
}

} // namespace retroprism::plot
