// approach_plot.h: the figures of `retroprism approach`: a sign's luminance and R_A for a driver
// approaching it (analysis/approach.h), the node against the MaterialX-style GGX fitted to the
// same R_A table; and two night previews side by side, each labelled.
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "approach.h"
#include "plot.h"

namespace retroprism::plot {

struct ApproachCurve {
    std::string label;
    Rgb color;
    std::vector<ApproachPoint> points;
};

// Two panels against the distance: the sign's luminance (cd m^-2) and its R_A at the
// observation and entrance angles of each distance, log scales; `caption` lines below.
OIIO::ImageBuf approach_figure(const std::string& title, const std::vector<ApproachCurve>& curves,
                               const std::vector<std::string>& caption, Text& text);

// The caption's first line for the one lamp of approach_luminance.
std::string lamp_caption(const ApproachSettings& s);

// The caption's first line for two headlamps from `files` (approach_headlamps; named without
// their folders): the vehicle, the sign's place, the road and the demand.
std::string headlamp_caption(const HeadlampSettings& s, const std::string& files);

// The display PNGs at `paths` side by side, each with its label above it.
OIIO::ImageBuf side_by_side(const std::vector<std::string>& paths,
                            const std::vector<std::string>& labels, Text& text);

} // namespace retroprism::plot
