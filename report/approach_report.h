// approach_report.h: what `retroprism approach` prints and writes besides its figures
// (approach_plot.h): the night preview of one model, the table of the sign's luminance on
// approach under one lamp (analysis/approach.h's approach_luminance) and, under two headlamps
// from files (approach_headlamps), the per-lamp angles and the supply beside the demand.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "approach.h"
#include "night_render.h"

namespace retroprism {

// The night preview's settings, shared by the two models `approach` renders.
struct NightPreview {
    NightSettings settings;
    double exposure = -6;
    std::string view = "aces";
};

// Renders `brdf` in the night scene and writes `exr` and the PNG beside it (same name,
// .png); prints both names. std::runtime_error, nothing written, when the BRDF returned NaN,
// infinite or negative values.
void write_night_preview(const LobeBrdf& brdf, const NightPreview& night, const std::string& exr,
                         const std::string& doc, const std::string& label, const Params& inputs);

// Every 30 m: observation and entrance angles, R_A and luminance of the node and the GGX.
void print_approach(const std::vector<ApproachPoint>& node, const std::vector<ApproachPoint>& mrm,
                    std::FILE* out);

// Every 30 m: per lamp (left, right) the observation, entrance, rotation and presentation
// angles and E_perp; then the sign's luminance of the node and the GGX beside the demand, and
// the R_A each supplies beside the R_A needed.
void print_headlamp_approach(const std::vector<HeadlampPoint>& node,
                             const std::vector<HeadlampPoint>& mrm, std::FILE* out);

} // namespace retroprism
