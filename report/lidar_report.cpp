#include "lidar_report.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "figure.h"

namespace retroprism {

namespace {

// The distinct values of a field of the rows, in their first order.
template <class T, class F>
std::vector<T> distinct(const std::vector<LidarRow>& rows, F field) {
    std::vector<T> v;
    for (const LidarRow& r : rows)
        if (std::find(v.begin(), v.end(), field(r)) == v.end()) v.push_back(field(r));
    return v;
}

std::vector<std::string> materials_of(const std::vector<LidarRow>& rows) {
    return distinct<std::string>(rows, [](const LidarRow& r) { return r.material; });
}
std::vector<double> wavelengths_of(const std::vector<LidarRow>& rows) {
    return distinct<double>(rows, [](const LidarRow& r) { return r.wavelength_nm; });
}
std::vector<double> entrances_of(const std::vector<LidarRow>& rows) {
    return distinct<double>(rows, [](const LidarRow& r) { return r.entrance_deg; });
}

// The rows of one material, wavelength and entrance angle, in range order.
std::vector<const LidarRow*> curve(const std::vector<LidarRow>& rows, const std::string& material,
                                   double nm, double entrance) {
    std::vector<const LidarRow*> c;
    for (const LidarRow& r : rows)
        if (r.material == material && r.wavelength_nm == nm && r.entrance_deg == entrance)
            c.push_back(&r);
    return c;
}

} // namespace

namespace {

// A block per material and wavelength, a row per range; per entrance angle the row's P_r/P, the
// value `other` gives for the row (by its index in `rows`) and P_r over it. `title` heads each
// block (after "MATERIAL at NM nm: "); with `albedo` the entrance heads give the albedo.
void print_blocks(const std::vector<LidarRow>& rows, const std::string& title,
                  const char* otherName, const std::function<double(std::size_t)>& other,
                  bool albedo, std::FILE* out) {
    const std::vector<double> entrances = entrances_of(rows);
    for (const std::string& m : materials_of(rows))
        for (double nm : wavelengths_of(rows)) {
            std::fprintf(out, "%s at %g nm: %s\n", m.c_str(), nm, title.c_str());
            std::fprintf(out, "%10s %10s", "", "");
            for (double b : entrances) {
                const std::vector<const LidarRow*> c = curve(rows, m, nm, b);
                if (albedo)
                    std::fprintf(out, " | entrance %3g deg, albedo %.3f ", b,
                                 c.empty() ? 0.0 : c[0]->albedo);
                else
                    std::fprintf(out, " | entrance %3g deg%15s", b, "");
            }
            std::fprintf(out, "\n%10s %10s", "range [m]", "obs [mrad]");
            for (std::size_t k = 0; k < entrances.size(); ++k)
                std::fprintf(out, " | %9s %9s %8s", "P_r/P", otherName, "ratio");
            std::fprintf(out, "\n");
            const std::vector<const LidarRow*> first = curve(rows, m, nm, entrances[0]);
            for (std::size_t i = 0; i < first.size(); ++i) {
                std::fprintf(out, "%10g %10.3f", first[i]->range_m, first[i]->observation_mrad);
                for (double b : entrances) {
                    const LidarRow* r = curve(rows, m, nm, b)[i];
                    const double o = other(std::size_t(r - rows.data()));
                    std::fprintf(out, " | %9.3e %9.3e %8.4g", r->ret.fraction, o,
                                 r->ret.fraction / o);
                }
                std::fprintf(out, "\n");
            }
            std::fprintf(out, "\n");
        }
}

} // namespace

void print_lidar_table(const std::vector<LidarRow>& rows, std::FILE* out) {
    print_blocks(
        rows,
        "returned fraction P_r/P; Lambertian: the Lambertian target of the same albedo; "
        "ratio: P_r over it",
        "Lambertian", [&](std::size_t i) { return rows[i].lambertian_albedo; }, true, out);
}

void print_lidar_model(const std::vector<LidarRow>& rows, const std::vector<LidarReturn>& model,
                       const std::string& modelLabel, std::FILE* out) {
    print_blocks(
        rows,
        "returned fraction P_r/P; model: " + modelLabel +
            " at the same geometry; ratio: P_r over the model's",
        "model", [&](std::size_t i) { return model[i].fraction; }, false, out);
}

void print_lidar_csv(const std::vector<LidarRow>& rows, std::FILE* out) {
    std::fprintf(out, "material,wavelength_nm,range_m,entrance_deg,observation_mrad,fraction,"
                      "reflectance,intercepted,albedo,lambertian_albedo_fraction\n");
    for (const LidarRow& r : rows)
        std::fprintf(out, "%s,%g,%g,%g,%.6g,%.6e,%.6g,%.6g,%.6g,%.6e\n", r.material.c_str(),
                     r.wavelength_nm, r.range_m, r.entrance_deg, r.observation_mrad, r.ret.fraction,
                     r.ret.reflectance, r.ret.intercepted, r.albedo, r.lambertian_albedo);
}

namespace plot {

namespace {

Panel range_panel(const std::vector<LidarRow>& rows, const std::string& material, double nm,
                  const std::vector<double>& entrances, const std::vector<double>& all) {
    Panel pan;
    pan.title = material + plot::fmt(" at %g nm", nm);
    pan.x_label = "range [m]";
    pan.x.log = true;
    double r0 = 1e300, r1 = 0;
    for (const LidarRow& r : rows)
        r0 = std::min(r0, r.range_m), r1 = std::max(r1, r.range_m);
    pan.x.lo = std::floor(std::log10(r0));
    pan.x.hi = std::ceil(std::log10(r1));
    pan.x.label = [](double d, double) { return fmt("%g", std::pow(10.0, d)); };
    pan.y.log = true;
    double v0 = 1e300, v1 = 0;
    for (double v : all)
        if (v > 0) v0 = std::min(v0, v), v1 = std::max(v1, v);
    pan.y.lo = std::floor(std::log10(v0));
    pan.y.hi = std::ceil(std::log10(v1));
    pan.y.step = pan.y.hi - pan.y.lo > 6 ? 2 : 1;
    for (std::size_t k = 0; k < entrances.size(); ++k) {
        Series node, lambert;
        node.color = lambert.color = kSeriesColor[k % 4];
        node.width = 3;
        lambert.width = 1;
        for (const LidarRow* r : curve(rows, material, nm, entrances[k])) {
            node.x.push_back(r->range_m);
            node.y.push_back(r->ret.fraction);
            lambert.x.push_back(r->range_m);
            lambert.y.push_back(r->lambertian_albedo);
        }
        pan.series.push_back(lambert);
        pan.series.push_back(node);
    }
    return pan;
}

} // namespace

OIIO::ImageBuf lidar_figure(const std::string& title, const std::vector<LidarRow>& rows,
                            const std::vector<std::string>& caption, Text& text) {
    const std::vector<double> entrances = entrances_of(rows), nms = wavelengths_of(rows);
    std::vector<double> all;
    for (const LidarRow& r : rows)
        all.push_back(r.ret.fraction), all.push_back(r.lambertian_albedo);
    Figure fig;
    fig.title = title;
    fig.subtitle = "returned fraction of the emitted power P_r / P";
    fig.cols = int(nms.size());
    fig.panel_width = 440;
    fig.panel_height = 300;
    fig.pad_left = 64;
    fig.pad_bottom = 56;
    for (const std::string& m : materials_of(rows))
        for (double nm : nms)
            fig.panels.push_back(range_panel(rows, m, nm, entrances, all));
    for (std::size_t k = 0; k < entrances.size(); ++k) {
        LegendEntry l;
        l.label = fmt("entrance %g deg", entrances[k]);
        l.style.color = kSeriesColor[k % 4];
        l.style.width = 3;
        fig.legend.push_back(l);
    }
    LegendEntry thin;
    thin.label = "thin: the Lambertian target of the same albedo";
    thin.style.color = kDimText;
    thin.style.width = 1;
    fig.legend.push_back(thin);
    fig.caption = caption;
    return render(fig, text);
}

} // namespace plot

} // namespace retroprism
