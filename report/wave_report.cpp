#include "wave_report.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "figure.h"
#include "study.h"

namespace retroprism {

namespace wave = sim::wave;

void print_wave_table(const wave::WaveMaterial& m, const std::vector<double>& lambdasNm,
                      const std::vector<double>& entranceDeg,
                      const std::vector<double>& observationDeg,
                      const std::vector<std::vector<std::vector<double>>>& ra, std::FILE* out) {
    std::fprintf(out,
                 "# wave R_A (sr^-1): ior %g, prism_reflection %d, cant %g deg, dihedral %g', "
                 "pitch %g um\n",
                 m.ior, m.prism_reflection, m.cant_deg, m.dihedral_arcmin, m.pitch_um);
    for (size_t l = 0; l < lambdasNm.size() && l < ra.size(); ++l) {
        if (lambdasNm[l] == 0)
            std::fprintf(out, "# photopic (illuminant A x V)\n");
        else
            std::fprintf(out, "# %g nm\n", lambdasNm[l]);
        std::fprintf(out, "%12s", "obs\\entr");
        for (double e : entranceDeg)
            std::fprintf(out, " %11g", e);
        std::fprintf(out, "\n");
        for (size_t a = 0; a < observationDeg.size(); ++a) {
            std::fprintf(out, "%12g", observationDeg[a]);
            for (const std::vector<double>& column : ra[l])
                std::fprintf(out, " %11.5g", column[a]);
            std::fprintf(out, "\n");
        }
    }
}

namespace {

// "ior 1.49, tir faces, cant 0 deg, dihedral 0', era_mode averaged".
std::string material_text(const Params& p, int prism) {
    const std::vector<std::string> eras = enum_values(*find_param("era_mode"));
    return plot::fmt("ior %g, ", p.ior) + sim::prism_name(prism) +
           plot::fmt(" faces, cant %g deg", p.cant_angle) +
           plot::fmt(", dihedral %g'", p.dihedral_error) + ", era_mode " +
           eras[size_t(std::clamp(p.era_mode, 0, int(eras.size()) - 1))];
}

// The wave optics' prism sizes: "pitches +-15%", or "one pitch".
std::string spread_text(double pitchSpread) {
    return pitchSpread > 0 ? plot::fmt("pitches +-%g%%", 100 * pitchSpread) : "one pitch";
}

} // namespace

void print_node_wave(const Params& material, const std::vector<wave::NodeWaveProfile>& profiles,
                     const std::vector<double>& observationDeg, double pitchSpread,
                     std::FILE* out) {
    const int prism = profiles.empty() ? material.prism_reflection : profiles[0].c.prism;
    std::fprintf(out,
                 "# node against wave optics, R_A (sr^-1) of the prisms alone, azimuth mean: %s; "
                 "wave optics: %s; node: roughness 1e-4, no surface lobe or substrate\n",
                 material_text(material, prism).c_str(), spread_text(pitchSpread).c_str());
    std::vector<double> ratios;
    for (const wave::NodeWaveProfile& p : profiles) {
        std::fprintf(out, "# %s, pitch %g um, %g nm, entrance %g deg\n", sim::prism_name(p.c.prism),
                     p.c.pitch_um, p.c.nm, p.c.entrance_deg);
        std::fprintf(out, "%12s %12s %12s %10s\n", "obs", "node", "wave", "node/wave");
        const std::vector<double> r = wave::node_wave_ratios(p);
        for (size_t a = 0; a < r.size() && a < observationDeg.size(); ++a)
            std::fprintf(out, "%12g %12.5g %12.5g %10.4f\n", observationDeg[a], p.node[a],
                         p.wave[a], r[a]);
        ratios.insert(ratios.end(), r.begin(), r.end());
    }
    const wave::NodeWaveCounts n = wave::node_wave_counts(ratios);
    std::fprintf(out,
                 "# node against wave optics: %ld of %ld entries within 10%%, %ld within a factor "
                 "2, worst factor %.2f\n",
                 n.within10, n.entries, n.within2x, n.worst_factor);
}

namespace plot {

std::vector<double> node_wave_plot_observations() {
    const int n = 60;
    const double lo = 0.05, hi = 3.0;
    std::vector<double> a;
    for (int i = 0; i < n; ++i)
        a.push_back(lo * std::pow(hi / lo, double(i) / (n - 1)));
    return a;
}

namespace {

const Rgb kWaveColor = kText, kNodeColor = kLobeColor[1];

Panel node_wave_panel(const wave::NodeWaveProfile& p, const std::vector<double>& obs) {
    Panel pan;
    pan.x.log = true;
    pan.x.lo = std::log10(obs.front());
    pan.x.hi = std::log10(obs.back());
    pan.x.label = [](double d, double) { return fmt("%g", std::pow(10.0, d)); };
    double lo = 1e300, hi = 0;
    for (const std::vector<double>* v : {&p.node, &p.wave})
        for (double r : *v)
            if (r > 0) lo = std::min(lo, r), hi = std::max(hi, r);
    pan.y.log = true;
    pan.y.hi = hi > 0 ? std::ceil(std::log10(hi)) : 1;
    pan.y.lo = hi > 0 ? std::max(std::floor(std::log10(lo)), pan.y.hi - 6) : 0;
    pan.y.label = [](double d, double) { return fmt("%g", std::pow(10.0, d)); };
    for (const auto& [values, color] :
         {std::pair{&p.wave, kWaveColor}, std::pair{&p.node, kNodeColor}}) {
        Series s;
        s.x = obs;
        s.y = *values;
        s.color = color;
        s.width = 2;
        pan.series.push_back(s);
    }
    const std::vector<double> r = wave::node_wave_ratios(p);
    const wave::NodeWaveCounts n = wave::node_wave_counts(r);
    const auto [least, most] = std::minmax_element(r.begin(), r.end());
    if (!r.empty())
        pan.title = fmt("node/wave %.2f", *least) + fmt(" to %.2f; ", *most) +
                    std::to_string(n.within10) + " of " + std::to_string(n.entries) + " within 10%";
    return pan;
}

// The distinct values of a field of the profiles' cases, in their first order.
template <class F>
std::vector<double> distinct(const std::vector<wave::NodeWaveProfile>& profiles, F field) {
    std::vector<double> v;
    for (const wave::NodeWaveProfile& p : profiles)
        if (std::find(v.begin(), v.end(), field(p.c)) == v.end()) v.push_back(field(p.c));
    return v;
}

} // namespace

OIIO::ImageBuf node_wave_figure(const Params& material,
                                const std::vector<wave::NodeWaveProfile>& profiles,
                                double pitchSpread, Text& text) {
    const std::vector<double> obs = node_wave_plot_observations();
    const std::vector<double> entrances =
        distinct(profiles, [](const wave::NodeWaveCase& c) { return c.entrance_deg; });
    const std::vector<double> nms =
        distinct(profiles, [](const wave::NodeWaveCase& c) { return c.nm; });
    const wave::NodeWaveCase first = profiles.empty() ? wave::NodeWaveCase() : profiles[0].c;
    Figure fig;
    fig.title = std::string("The node's diffraction lobe against physical optics: ") +
                sim::prism_name(first.prism) + fmt(" faces, pitch %g um", first.pitch_um);
    fig.subtitle = "R_A [cd lx^-1 m^-2] of the prisms alone, mean over the observation azimuth, "
                   "against the observation angle";
    fig.cols = int(nms.size());
    fig.top = 112;
    fig.left = 150;
    fig.panel_width = 330;
    fig.panel_height = 230;
    fig.pad_left = 60;
    fig.pad_top = 30;
    fig.pad_bottom = 34;
    for (double nm : nms)
        fig.col_heads.push_back(fmt("%g nm", nm));
    Panel none; // a case the profiles do not hold
    none.frame = false;
    for (double e : entrances) {
        fig.row_heads.push_back(fmt("entrance %g deg", e));
        for (double nm : nms) {
            const auto p = std::find_if(profiles.begin(), profiles.end(), [&](const auto& q) {
                return q.c.entrance_deg == e && q.c.nm == nm;
            });
            fig.panels.push_back(p != profiles.end() ? node_wave_panel(*p, obs) : none);
        }
    }
    fig.x_label = "observation angle [deg]";
    LegendEntry truth, node;
    truth.label = "wave optics (orientation average, " + spread_text(pitchSpread) + ")";
    truth.style.color = kWaveColor;
    node.label = "node (roughness 1e-4, the retro lobe alone)";
    node.style.color = kNodeColor;
    fig.legend = {truth, node};
    fig.caption = {material_text(material, first.prism) +
                   "; R_A of the node and of the wave optics (sim/wave_node.h) at 60 angles "
                   "log-spaced over 0.05-3 deg"};
    return render(fig, text);
}

} // namespace plot

} // namespace retroprism
