// approach_plot.cpp: the figures of `retroprism approach` (see approach_plot.h).
#include "approach_plot.h"

#include <algorithm>
#include <cmath>

#include <OpenImageIO/imagebufalgo.h>

#include "error.h"
#include "figure.h"

namespace retroprism::plot {

namespace {

Panel distance_panel(const std::string& heading, const std::vector<ApproachCurve>& curves,
                     double ApproachPoint::*value) {
    Panel pan;
    pan.heading = heading;
    pan.x.lo = 0;
    pan.x.hi = 0;
    std::vector<double> all;
    for (const ApproachCurve& c : curves) {
        Series s;
        s.color = c.color;
        s.width = 2;
        for (const ApproachPoint& p : c.points) {
            s.x.push_back(p.distance);
            s.y.push_back(p.*value);
            all.push_back(p.*value);
            pan.x.hi = std::max(pan.x.hi, p.distance);
        }
        pan.series.push_back(s);
    }
    pan.x.label = [](double v, double) { return fmt("%.0f", v); };
    pan.x_label = "distance to the sign [m]";
    double lo = 1e300, hi = -1e300;
    for (double v : all)
        if (v > 0) {
            lo = std::min(lo, std::log10(v));
            hi = std::max(hi, std::log10(v));
        }
    pan.y.log = true;
    pan.y.hi = std::ceil(hi + 0.05);
    pan.y.lo = std::max(std::floor(lo - 0.05), pan.y.hi - 5.0);
    pan.y.label = [](double d, double) { return fmt("%g", std::pow(10.0, d)); };
    return pan;
}

} // namespace

OIIO::ImageBuf approach_figure(const std::string& title, const std::vector<ApproachCurve>& curves,
                               const std::vector<std::string>& caption, Text& text) {
    Figure fig;
    fig.title = title;
    fig.cols = 2;
    fig.panel_width = 480;
    fig.panel_height = 320;
    fig.pad_left = 64;
    fig.pad_bottom = 56;
    fig.panels = {
        distance_panel("sign luminance [cd m^-2]", curves, &ApproachPoint::luminance),
        distance_panel("R_A [cd lx^-1 m^-2] at the driver's geometry", curves, &ApproachPoint::ra)};
    for (const ApproachCurve& c : curves) {
        LegendEntry l;
        l.label = c.label;
        l.style.width = 3;
        l.style.color = c.color;
        fig.legend.push_back(l);
    }
    fig.caption = caption;
    return render(fig, text);
}

std::string lamp_caption(const ApproachSettings& s) {
    return fmt("Low beam: %g cd toward the sign", s.lamp_cd) +
           fmt("; the driver's eye %g m above the headlamp", s.eye_above_lamp) +
           fmt("; the sign %g m right and", s.sign_right) +
           fmt(" %g m above the headlamp, facing the road.", s.sign_up);
}

std::string headlamp_caption(const HeadlampSettings& s, const std::string& files) {
    const Vehicle& v = s.vehicle;
    std::string names; // the files without their folders
    for (size_t start = 0; start <= files.size();) {
        const size_t comma = std::min(files.find(',', start), files.size());
        const std::string f = files.substr(start, comma - start);
        names += (start > 0 ? "," : "") + f.substr(f.rfind('/') + 1);
        start = comma + 1;
    }
    return "Low beams: " + names + " (" + v.name + fmt(": lamps %g m apart, ", v.lamp_spacing) +
           fmt("%g m up; eye ", v.lamp_height) + fmt("%g m up, ", v.eye_height) +
           fmt("%g m left); sign ", v.eye_left) + fmt("%g m right, ", s.sign_right) +
           fmt("%g m up; ", s.sign_height) +
           (s.curve_radius == 0 ? std::string("straight road")
                                : fmt("curve radius %g m", s.curve_radius)) +
           fmt("; needed %g cd m^-2.", s.demand_cd_m2);
}

OIIO::ImageBuf side_by_side(const std::vector<std::string>& paths,
                            const std::vector<std::string>& labels, Text& text) {
    namespace IBA = OIIO::ImageBufAlgo;
    std::vector<OIIO::ImageBuf> images;
    int w = 0, h = 0;
    for (const std::string& p : paths) {
        OIIO::ImageBuf img(p);
        if (!img.read(0, 0, true, OIIO::TypeDesc::FLOAT))
            throw InputError(p + ": cannot read (" + img.geterror() + ")");
        w += img.spec().width;
        h = std::max(h, img.spec().height);
        images.push_back(std::move(img));
    }
    const int head = 34, gap = 8;
    OIIO::ImageBuf out(
        OIIO::ImageSpec(w + gap * int(images.size() - 1), h + head, 3, OIIO::TypeDesc::FLOAT));
    IBA::fill(out, kBackground);
    int x = 0;
    for (size_t i = 0; i < images.size(); ++i) {
        OIIO::ROI rgb = images[i].roi();
        rgb.chbegin = 0;
        rgb.chend = std::min(rgb.chend, 3);
        IBA::paste(out, x, head, 0, 0, images[i], rgb);
        text.draw(out, x + 8, 24, i < labels.size() ? labels[i] : "", 18, kText);
        x += images[i].spec().width + gap;
    }
    return out;
}

} // namespace retroprism::plot
