#include "ra_print.h"

#include "ra_fit.h"

namespace retroprism {

void print_ra_table(const RaTable& t, const std::string& material, bool rgb, std::FILE* out) {
    std::fprintf(out,
                 "R_A [cd lx^-1 m^-2] of %s, rotation epsilon = %g deg (coplanar geometry; rows: "
                 "observation angle alpha, columns: entrance angle beta)\n",
                 material.c_str(), t.rotation);
    const char* names[4] = {"Y (Rec.709 luminance)", "R", "G", "B"};
    for (int part = 0; part < (rgb ? 4 : 1); ++part) {
        if (rgb) std::fprintf(out, "%s\n", names[part]);
        std::fprintf(out, "%14s", "alpha \\ beta");
        for (double b : t.entrance)
            std::fprintf(out, " %9g", b);
        std::fprintf(out, "\n");
        for (size_t r = 0; r < t.observation.size(); ++r) {
            std::fprintf(out, "%14g", t.observation[r]);
            for (size_t c = 0; c < t.entrance.size(); ++c) {
                const glm::dvec3& v = t.rgb[r][c];
                const double x = part == 0 ? luminance_709(v) : v[part - 1];
                std::fprintf(out, " %9.2f", x);
            }
            std::fprintf(out, "\n");
        }
    }
}

void print_ra_csv(const RaTable& t, std::FILE* out) {
    std::fprintf(out, "observation_deg,entrance_deg,rotation_deg,R_A_Y,R_A_R,R_A_G,R_A_B\n");
    for (size_t r = 0; r < t.observation.size(); ++r)
        for (size_t c = 0; c < t.entrance.size(); ++c) {
            const glm::dvec3& v = t.rgb[r][c];
            std::fprintf(out, "%g,%g,%g,%.9g,%.9g,%.9g,%.9g\n", t.observation[r], t.entrance[c],
                         t.rotation, luminance_709(v), v.x, v.y, v.z);
        }
}

void print_ra_comparison(const RaMeasurements& t, const std::vector<RaModelValues>& models,
                         std::FILE* out) {
    std::fprintf(out, "%6s %9s %9s %9s %9s %10s", "line", "observ.", "entrance", "rotation",
                 "present.", "measured");
    for (const RaModelValues& m : models)
        std::fprintf(out, " %10s %8s", m.first.c_str(), "error");
    std::fprintf(out, "\n");
    for (size_t i = 0; i < t.entries.size(); ++i) {
        const RaEntry& e = t.entries[i];
        const std::string rotation =
            e.rotation_deg ? std::to_string(*e.rotation_deg).substr(0, 8) : "mean";
        std::fprintf(out, "%6d %9g %9g %9s %9g %10.4g", e.line, e.observation_deg, e.entrance_deg,
                     rotation.c_str(), e.presentation_deg, e.ra);
        for (const RaModelValues& m : models)
            std::fprintf(out, " %10.4g %+7.1f%%", m.second[i], 100.0 * (m.second[i] - e.ra) / e.ra);
        std::fprintf(out, "\n");
    }
    for (const RaModelValues& m : models) {
        const RaFitReport r = ra_fit_report(t, m.second);
        std::fprintf(out,
                     "%s: RMS of ln(model / measured) %.4f, largest error %.1f%% over %zu rows\n",
                     m.first.c_str(), r.log_rms, 100.0 * r.max_error, t.entries.size());
    }
}

} // namespace retroprism
