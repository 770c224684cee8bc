// cost_error_plot.h: the plot of `retroprism bench --plot`: ns per evaluation against the
// relative L1 error of each row, both on log scales, with the Pareto front (rows no other row
// beats in both cost and error), the baseline's cost and the targets at 2x and 6x of it.
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

namespace retroprism::plot {

struct CostErrorPoint {
    std::string name;
    double ns = 0;    // per evaluation
    double error = 0; // relative L1 error (<= 0: none, left out)
};

// baselineNs: the MaterialX retroreflective GGX's cost (<= 0: none drawn).
OIIO::ImageBuf cost_error_figure(const std::vector<CostErrorPoint>& points, double baselineNs);

} // namespace retroprism::plot
