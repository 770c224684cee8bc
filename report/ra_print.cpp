#include "ra_print.h"

#include <filesystem>

#include "plot.h"

namespace retroprism {

namespace {

std::string rotation_text(const RaEntry& e) {
    return e.rotation_deg ? std::to_string(*e.rotation_deg).substr(0, 8) : "mean";
}

} // namespace

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
        const std::string rotation = rotation_text(e);
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

void print_standard_list(std::FILE* out) {
    std::fprintf(out, "bundled standard tables (retroprism ra --standard NAME):\n");
    for (const std::string& name : standard_names()) {
        const RaMeasurements t = read_standard(name);
        std::fprintf(out, "  %-36s %s\n", name.c_str(),
                     t.comments.empty() ? "" : t.comments.front().c_str());
    }
}

void print_standard_judgement(const std::string& name, const StandardJudgement& j,
                              const std::string& material, std::FILE* out) {
    std::fprintf(out, "R_A [cd lx^-1 m^-2] of %s against the minimums of %s, colour %s\n",
                 material.c_str(), name.c_str(), j.color.c_str());
    std::fprintf(out, "%6s %9s %9s %9s %10s %10s %9s %6s\n", "line", "observ.", "entrance",
                 "rotation", "minimum", "material", "margin", "result");
    size_t passed = 0;
    for (const StandardEntry& s : j.entries) {
        const RaEntry& e = s.entry;
        passed += s.pass ? 1 : 0;
        std::fprintf(out, "%6d %9g %9g %9s %10.4g %10.4g %+8.1f%% %6s\n", e.line, e.observation_deg,
                     e.entrance_deg, rotation_text(e).c_str(), e.ra, s.material,
                     100.0 * (s.material / e.ra - 1.0), s.pass ? "pass" : "FAIL");
    }
    std::fprintf(out, "%s, colour %s: %s (%zu of %zu entries at or above the minimum)\n",
                 name.c_str(), j.color.c_str(), j.pass ? "pass" : "FAIL", passed, j.entries.size());
}

void print_ra_color_fits(const std::vector<RaColorFit>& colors, std::FILE* out) {
    for (const RaColorFit& c : colors)
        std::fprintf(out,
                     "colour %-24s retro_color (%.4g, %.4g, %.4g)%s: RMS of ln(model / "
                     "measured) %.4f, largest error %.1f%% over its %zu rows\n",
                     c.color.c_str(), c.retro_color[0], c.retro_color[1], c.retro_color[2],
                     c.hue || c.color == "white" ? "" : " (grey: its luminance only)",
                     c.report.log_rms, 100.0 * c.report.max_error, c.report.model.size());
}

std::vector<std::string> ra_fit_document_comment(const RaMeasurements& t, const RaNodeFit& nf,
                                                 const RaMrmFit& mf) {
    std::vector<std::string> c = {"The prismatic retroreflector node fitted by retroprism fit to "
                                  "the R_A table " +
                                  std::filesystem::path(t.file).filename().string() + ":"};
    for (const std::string& line : t.comments)
        c.push_back("  " + line);
    std::string fitted;
    for (const std::string& n : nf.fitted)
        fitted += (fitted.empty() ? "" : ", ") + n;
    c.push_back("Fitted inputs: " + fitted + "; the others are the base material's.");
    c.push_back(plot::fmt("Fit: RMS of ln(fitted / measured) %.4f", nf.report.log_rms) +
                plot::fmt(", largest error %.1f%%", 100 * nf.report.max_error) + " over " +
                std::to_string(t.entries.size()) + " rows (R_A in cd lx^-1 m^-2):");
    for (size_t i = 0; i < t.entries.size(); ++i) {
        const RaEntry& e = t.entries[i];
        c.push_back(
            plot::fmt("  observation %g deg", e.observation_deg) +
            plot::fmt(", entrance %g deg", e.entrance_deg) +
            (e.rotation_deg ? plot::fmt(", rotation %g deg", *e.rotation_deg) : "") +
            (e.presentation_deg != 0 ? plot::fmt(", presentation %g", e.presentation_deg) : "") +
            plot::fmt(": measured %g", e.ra) + plot::fmt(", fitted %.4g", nf.report.model[i]) +
            plot::fmt(" (%+.1f%%)", 100 * nf.report.error[i]));
    }
    c.push_back(plot::fmt("The MaterialX-style retroreflective GGX fitted to the same table: RMS "
                          "of ln %.4f",
                          mf.report.log_rms) +
                plot::fmt(", largest error %.1f%%.", 100 * mf.report.max_error));
    return c;
}

std::string ra_fit_input_text(const Params& p, const std::string& name) {
    const ParamInfo& info = *find_param(name);
    switch (info.type) {
    case ParamType::Float:
        return plot::fmt("%.6g", *input_field<double>(p, name));
    case ParamType::Color: {
        const Color3& c = *input_field<Color3>(p, name);
        if (c[0] == c[1] && c[1] == c[2]) return plot::fmt("%.6g", c[0]) + " (grey)";
        return plot::fmt("(%.6g, ", c[0]) + plot::fmt("%.6g, ", c[1]) + plot::fmt("%.6g)", c[2]);
    }
    case ParamType::Enum:
        return enum_values(info).at(size_t(*input_field<int>(p, name)));
    default:
        return *input_field<bool>(p, name) ? "true" : "false";
    }
}

} // namespace retroprism
