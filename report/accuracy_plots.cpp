// accuracy_plots.cpp: the accuracy study's plots (see accuracy_plots.h).
#include "accuracy_plots.h"

#include <cmath>

#include "figure.h"

namespace retroprism::report {

namespace {

using plot::Rgb;

enum Kind { kInPlane, kAcross, kSlices };
const char* const kKindPrefix[3] = {"retro_inplane_", "retro_across_", "slices_"};

std::string tag_of(double eta, int prism) {
    return plot::fmt("eta%g_", eta) + sim::prism_name(prism);
}

plot::Series line(const std::vector<double>& x, const std::vector<double>& y, const Rgb& c,
                  int width = 2) {
    plot::Series s;
    s.x = x;
    s.y = y;
    s.color = c;
    s.width = width;
    return s;
}

// Simulated values as points with +-2 standard error bars.
plot::Series sim_points(const std::vector<double>& x, const std::vector<sim::Estimate>& es,
                        const Rgb& c) {
    plot::Series s;
    s.x = x;
    s.color = c;
    s.points = true;
    s.width = 1;
    for (const sim::Estimate& e : es) {
        s.y.push_back(e.value);
        s.err.push_back(e.se);
    }
    return s;
}

// The values (plus 2 standard errors) of the series within the x range, for the autoscale.
std::vector<double> visible_values(const plot::Panel& pan) {
    std::vector<double> out;
    for (const plot::Series& s : pan.series)
        for (size_t i = 0; i < s.y.size(); ++i)
            if (s.x[i] >= pan.x.lo && s.x[i] <= pan.x.hi && std::isfinite(s.y[i]))
                out.push_back(s.y[i] + (s.err.empty() ? 0 : 2 * s.err[i]));
    return out;
}

// The retro lobe's centre row (along) or column (across): four variants against the simulation.
plot::Panel lobe_panel(const sim::ConfigResult& r, bool along) {
    plot::Panel pan;
    const std::vector<double>& xs = along ? r.sim.rowX : r.sim.colX;
    pan.x.lo = xs.front();
    pan.x.hi = xs.back();
    for (int v = 0; v < 4; ++v)
        pan.series.push_back(line(xs, along ? r.v[size_t(v)].row : r.v[size_t(v)].col,
                                  plot::kSeriesColor[v], v == 0 ? 3 : 2));
    pan.series.push_back(sim_points(xs, along ? r.sim.row : r.sim.col, plot::kLobeColor[3]));
    plot::fit_linear(pan.y, visible_values(pan));
    pan.y.label = [](double v, double step) { return plot::fmt(step < 0.01 ? "%.1e" : "%g", v); };
    pan.title = "fit " + plot::fmt("%.3g", along ? r.sim.fit.ax : r.sim.fit.ay) + ", aniso " +
                plot::fmt("%.3g", along ? r.v[1].alphaPar : r.v[1].alphaPerp) + ", iso " +
                plot::fmt("%.3g", r.v[0].alphaPar);
    return pan;
}

// The whole BRDF in the plane of incidence (total and diffuse), log scale.
plot::Panel slice_panel(const sim::ConfigResult& r) {
    plot::Panel pan;
    pan.x.lo = -90;
    pan.x.hi = 90;
    plot::Marker retro, mirror;
    retro.x = r.c.theta;
    retro.color = plot::kSeriesColor[0];
    mirror.x = -r.c.theta;
    mirror.color = plot::kDimText;
    pan.markers = {retro, mirror};
    const std::vector<double>& xs = r.sim.stripX;
    for (int v : {0, 3}) {
        pan.series.push_back(line(xs, r.v[size_t(v)].strip[3], plot::kSeriesColor[v]));
        pan.series.push_back(
            line(xs, r.v[size_t(v)].strip[2], v == 3 ? plot::kTeal : plot::kLobeColor[2]));
    }
    pan.series.push_back(sim_points(xs, r.sim.strip[3], plot::kLobeColor[3]));
    pan.series.push_back(sim_points(xs, r.sim.strip[2], plot::kLobeColor[2]));
    plot::fit_log(pan.y, visible_values(pan), 5, 0.02);
    pan.title = plot::fmt("sim diffuse(n) %.3g", r.sim.diffuseNormal.value) +
                plot::fmt(", paper %.3g", r.v[0].diffuseNormal) +
                plot::fmt(", recip. %.3g", r.v[2].diffuseNormal);
    return pan;
}

plot::LegendEntry legend_line(const std::string& label, const Rgb& c, int width = 2) {
    plot::LegendEntry e;
    e.label = label;
    e.style.color = c;
    e.style.width = width;
    return e;
}

plot::LegendEntry legend_point(const std::string& label, const Rgb& c) {
    plot::LegendEntry e = legend_line(label, c);
    e.style.points = true;
    e.style.width = 3;
    return e;
}

// The texts and legend of a figure of `kind`.
void label_figure(plot::Figure& fig, Kind kind, double eta, int prism, double rays) {
    const std::string material =
        "(ior " + plot::fmt("%g", eta) + ", " + sim::prism_name(prism) + " prisms, k_d 0.9)";
    if (kind == kSlices) {
        fig.title = "In-plane slices, log scale: simulation vs analytic " + material;
        fig.x_label = "signed theta_o [deg] (> 0: the light's side; retro peak at +theta_i, "
                      "mirror at -theta_i)";
        fig.subtitle = "f [1/sr] (total and diffuse), 2-degree cells of a 4-degree-wide strip";
        fig.legend = {legend_line("total, paper form", plot::kSeriesColor[0]),
                      legend_line("total, aniso + reciprocal", plot::kSeriesColor[3]),
                      legend_line("diffuse, paper (1-E_i)", plot::kLobeColor[2]),
                      legend_line("diffuse, reciprocal sqrt((1-E_i)(1-E_o))", plot::kTeal),
                      legend_point("simulation total", plot::kLobeColor[3]),
                      legend_point("simulation diffuse", plot::kLobeColor[2])};
        fig.caption = {"Panel titles: the diffuse lobe's f at the normal (5-degree cone), "
                       "simulation vs the paper's form and the reciprocal form."};
        return;
    }
    const bool along = kind == kInPlane;
    fig.title = "Retro lobe " +
                std::string(along ? "in the plane of incidence" : "across the plane of incidence") +
                ": simulation vs analytic variants " + material;
    fig.x_label = along ? "angle from wi in the plane of incidence [deg] (> 0: toward the horizon)"
                        : "angle from wi across the plane of incidence [deg]";
    fig.subtitle = "f_r [1/sr], cosine-weighted cell averages of the retro grid's centre " +
                   std::string(along ? "row" : "column");
    for (int v = 0; v < 4; ++v)
        fig.legend.push_back(legend_line(sim::kVariants[v].name, plot::kSeriesColor[v], 3));
    fig.legend.push_back(legend_point("simulation (+-2 se)", plot::kLobeColor[3]));
    fig.caption = {"Panel titles: the simulation's fitted Beckmann width along this direction, "
                   "and the anisotropic and isotropic variants' widths (slopes).",
                   plot::fmt("%.3g rays per panel; reciprocal variants evaluated as the node does "
                             "(E and the lobe at the mean direction of wi and wo).",
                             rays)};
}

} // namespace

std::vector<std::string> accuracy_plot_names(const sim::StudyGrid& grid) {
    std::vector<std::string> out;
    for (double eta : grid.etas)
        for (int prism : grid.prisms)
            for (const char* prefix : kKindPrefix)
                out.push_back(prefix + tag_of(eta, prism) + ".png");
    return out;
}

void write_accuracy_plots(const sim::StudyResults& study, const std::string& dir) {
    plot::Text text("retroprism simulate");
    const sim::StudyGrid& g = study.grid;
    for (double eta : g.etas)
        for (int prism : g.prisms)
            for (Kind kind : {kInPlane, kAcross, kSlices}) {
                plot::Figure fig;
                fig.left = 110;
                fig.cols = int(g.thetas.size());
                for (double t : g.thetas)
                    fig.col_heads.push_back(plot::fmt("theta_i = %g deg", t));
                for (double a : g.alphas)
                    fig.row_heads.push_back(plot::fmt("alpha %g", a));
                for (double alpha : g.alphas)
                    for (double theta : g.thetas) {
                        const sim::ConfigResult& r = study.at(theta, alpha, eta, prism);
                        fig.panels.push_back(kind == kSlices ? slice_panel(r)
                                                             : lobe_panel(r, kind == kInPlane));
                    }
                label_figure(fig, kind, eta, prism, double(study.options.rays));
                plot::write_png(plot::render(fig, text),
                                dir + "/" + kKindPrefix[kind] + tag_of(eta, prism) + ".png");
            }
}

} // namespace retroprism::report
