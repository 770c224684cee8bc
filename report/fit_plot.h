// fit_plot.h: the plot of `retroprism fit --plot`: per incidence angle theta_l, the measured
// in-plane samples against the two fitted models (the node and the MaterialX-style
// retroreflective GGX), log scale, with each model's errors under the panel.
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "plot.h"

namespace retroprism::plot {

// One in-plane slice of a theta_l group: measured samples (signed theta_v, value) and the two
// fits on a dense grid.
struct FitSlice {
    double thetaDeg = 0;
    std::vector<double> ms, mv;                              // measured: signed angle (deg), value
    std::vector<double> s, node, mrm;                        // curves
    double nodeRel = 0, nodeLog = 0, mrmRel = 0, mrmLog = 0; // the group's errors
};

// fileName: the data file's name, for the title.
OIIO::ImageBuf fit_figure(const std::string& fileName, const std::vector<FitSlice>& slices,
                          Text& text);

} // namespace retroprism::plot
