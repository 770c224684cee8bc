// fit_plot.h: the plots of `retroprism fit --plot`: per incidence angle theta_l, the measured
// in-plane samples against the two fitted models (the node and the MaterialX-style
// retroreflective GGX), log scale, with each model's errors under the panel; for an R_A table
// (`fit --ra`), R_A against the observation angle per entrance angle, measured points and the
// two fits' curves, log scale.
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "plot.h"
#include "ra_fit.h"

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

// One panel per entrance angle (and rotation and presentation angle, when the table has several
// of them at one entrance angle): R_A [cd lx^-1 m^-2] against the observation angle, the
// measured entries as points, the fitted node and baseline as curves from 0.02 degrees to
// beyond the largest measured observation angle, each panel's largest errors under it.
OIIO::ImageBuf ra_fit_figure(const RaMeasurements& t, const RaNodeFit& node, const RaMrmFit& mrm,
                             Text& text);

} // namespace retroprism::plot
