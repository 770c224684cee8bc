// approach_report.cpp: see approach_report.h.
#include "approach_report.h"

#include <cmath>
#include <stdexcept>

#include "night_output.h"

namespace retroprism {

namespace {

bool printed(double distance) {
    return std::fmod(distance + 1e-9, 30.0) <= 1e-6;
}

} // namespace

void write_night_preview(const LobeBrdf& brdf, const NightPreview& night, const std::string& exr,
                         const std::string& doc, const std::string& label, const Params& inputs) {
    const NightImage img = render_night(brdf, night.settings);
    if (img.anomalies > 0)
        throw std::runtime_error(label + ": " + std::to_string(img.anomalies) +
                                 " NaN, infinite or negative BRDF values; nothing written");
    std::string png = exr.substr(0, exr.rfind('.')) + ".png";
    write_night_images(img, {exr, png, night.view, night.exposure, doc, label, inputs, false, ""});
    std::printf("wrote %s, %s\n", exr.c_str(), png.c_str());
}

void print_approach(const std::vector<ApproachPoint>& node, const std::vector<ApproachPoint>& mrm,
                    std::FILE* out) {
    std::fprintf(out, "\n%10s %12s %12s %12s %12s %12s %12s\n", "distance", "observation",
                 "entrance", "R_A node", "R_A mrm", "L node", "L mrm");
    for (size_t i = 0; i < node.size(); ++i) {
        const ApproachPoint& a = node[i];
        if (!printed(a.distance)) continue;
        std::fprintf(out, "%8.0f m %10.3f d %10.3f d %12.4g %12.4g %12.4g %12.4g\n", a.distance,
                     a.observation_deg, a.entrance_deg, a.ra, mrm[i].ra, a.luminance,
                     mrm[i].luminance);
    }
    std::fprintf(out, "(R_A in cd lx^-1 m^-2, sign luminance L in cd m^-2)\n");
}

void print_headlamp_approach(const std::vector<HeadlampPoint>& node,
                             const std::vector<HeadlampPoint>& mrm, std::FILE* out) {
    std::fprintf(out, "\n%10s %5s %11s %9s %9s %13s %10s\n", "distance", "lamp", "observation",
                 "entrance", "rotation", "presentation", "E_perp");
    for (const HeadlampPoint& p : node) {
        if (!printed(p.distance)) continue;
        for (int k = 0; k < 2; ++k) {
            const LampAtSign& l = p.lamps[k];
            std::fprintf(out, "%8.0f m %5s %9.3f d %7.2f d %7.1f d %11.1f d %10.4g\n", p.distance,
                         k == 0 ? "left" : "right", l.angles.observation, l.angles.entrance,
                         l.angles.rotation, l.angles.presentation, l.illuminance);
        }
    }
    std::fprintf(out, "\n%10s %10s %10s %10s %12s %12s %12s\n", "distance", "L node", "L mrm",
                 "L needed", "R_A node", "R_A mrm", "R_A needed");
    for (size_t i = 0; i < node.size(); ++i) {
        const HeadlampPoint& p = node[i];
        if (!printed(p.distance)) continue;
        std::fprintf(out, "%8.0f m %10.4g %10.4g %10.4g %12.4g %12.4g %12.4g\n", p.distance,
                     p.luminance, mrm[i].luminance, p.demand, p.ra_supplied, mrm[i].ra_supplied,
                     p.ra_needed);
    }
    std::fprintf(out, "(angles in degrees at the sign's centre, E_perp in lx, L in cd m^-2, R_A "
                      "in cd lx^-1 m^-2: the lamps' R_A weighted by their illuminance; R_A "
                      "needed = L needed cos(theta_o) / (E_left + E_right), 0 where the lamps "
                      "do not light the sign)\n");
}

} // namespace retroprism
