// fit_plot.cpp: the fit's comparison plot (see fit_plot.h).
#include "fit_plot.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

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

namespace {

// The entries of one panel: one entrance angle, rotation (NaN: the mean over 0 and 90 degrees)
// and presentation angle.
using PanelKey = std::tuple<double, double, double>;

PanelKey panel_key(const RaEntry& e) {
    return {e.entrance_deg, e.rotation_deg ? *e.rotation_deg : -1e9, e.presentation_deg};
}

std::string panel_heading(const RaEntry& e) {
    std::string h = fmt("entrance %g deg", e.entrance_deg);
    if (e.rotation_deg) h += fmt(", rotation %g", *e.rotation_deg);
    if (e.presentation_deg != 0) h += fmt(", presentation %g", e.presentation_deg);
    return h;
}

LegendEntry legend(const std::string& label, const Rgb& c, bool points) {
    LegendEntry l;
    l.label = label;
    l.style.points = points;
    l.style.width = 3;
    l.style.color = c;
    return l;
}

} // namespace

OIIO::ImageBuf ra_fit_figure(const RaMeasurements& t, const RaNodeFit& node, const RaMrmFit& mrm,
                             Text& text) {
    std::map<PanelKey, std::vector<size_t>> groups;
    double obsMax = 0;
    for (size_t i = 0; i < t.entries.size(); ++i) {
        groups[panel_key(t.entries[i])].push_back(i);
        obsMax = std::max(obsMax, t.entries[i].observation_deg);
    }
    const double xHi = std::min(5.0, std::ceil(obsMax * 1.25 * 10.0) / 10.0);
    const Rgb nodeColor = kLobeColor[1], mrmColor = kLobeColor[0];
    // The curves, and one vertical range over them and the measurements.
    std::vector<double> all;
    struct Curves {
        std::vector<double> x, node, mrm;
    };
    std::vector<Curves> curves;
    for (const auto& g : groups) {
        std::vector<RaEntry> grid;
        Curves c;
        for (int k = 0; k <= 120; ++k) {
            RaEntry e = t.entries[g.second.front()];
            e.observation_deg = 0.02 + (xHi - 0.02) * k / 120.0;
            grid.push_back(e);
            c.x.push_back(e.observation_deg);
        }
        c.node = ra_node_values(node.params, grid);
        c.mrm = ra_mrm_values(mrm.model, grid);
        for (size_t i : g.second)
            all.push_back(t.entries[i].ra);
        all.insert(all.end(), c.node.begin(), c.node.end());
        curves.push_back(std::move(c));
    }
    double lo = 1e300, hi = -1e300;
    for (double v : all)
        if (v > 0) {
            lo = std::min(lo, std::log10(v));
            hi = std::max(hi, std::log10(v));
        }
    const double yHi = std::ceil(hi + 0.05), yLo = std::max(std::floor(lo - 0.05), yHi - 4.0);

    Figure fig;
    fig.title = "fit of " + t.file.substr(t.file.find_last_of('/') + 1) +
                ": R_A [cd lx^-1 m^-2] against observation angle";
    fig.cols = std::min<int>(3, int(groups.size()));
    fig.panel_width = 380;
    fig.panel_height = 300;
    fig.pad_left = 64;
    fig.pad_top = 50;
    fig.pad_bottom = 100;
    size_t gi = 0;
    for (const auto& g : groups) {
        const Curves& c = curves[gi++];
        Panel pan;
        pan.heading = panel_heading(t.entries[g.second.front()]);
        pan.x.lo = 0;
        pan.x.hi = xHi;
        pan.x_label = "observation angle [deg]";
        pan.y.log = true;
        pan.y.lo = yLo;
        pan.y.hi = yHi;
        pan.y.label = [](double d, double) { return fmt("%g", std::pow(10.0, d)); };
        for (const auto& [v, color] :
             {std::pair{&c.mrm, mrmColor}, std::pair{&c.node, nodeColor}}) {
            Series s;
            s.x = c.x;
            s.y = *v;
            s.color = color;
            s.width = 2;
            pan.series.push_back(s);
        }
        Series m;
        m.points = true;
        m.width = 3;
        m.color = kText;
        double nodeErr = 0, mrmErr = 0;
        for (size_t i : g.second) {
            m.x.push_back(t.entries[i].observation_deg);
            m.y.push_back(t.entries[i].ra);
            nodeErr = std::max(nodeErr, std::abs(node.report.error[i]));
            mrmErr = std::max(mrmErr, std::abs(mrm.report.error[i]));
        }
        pan.series.push_back(m);
        pan.lines_below = {{fmt("node: largest error %.1f%%", 100 * nodeErr), nodeColor},
                           {fmt("mrm:  largest error %.1f%%", 100 * mrmErr), mrmColor}};
        fig.panels.push_back(pan);
    }
    fig.legend = {legend("measured", kText, true),
                  legend("node fit (prismatic retroreflector)", nodeColor, false),
                  legend("mrm fit (MaterialX retroreflective GGX + Lambert)", mrmColor, false)};
    fig.caption = {fmt("node: log RMS %.3f", node.report.log_rms) +
                       fmt(", largest error %.1f%%", 100 * node.report.max_error) +
                       fmt(";  mrm: log RMS %.3f", mrm.report.log_rms) +
                       fmt(", largest error %.1f%%", 100 * mrm.report.max_error),
                   "rows without a rotation angle: the mean over rotations 0 and 90 degrees"};
    return render(fig, text);
}

} // namespace retroprism::plot
