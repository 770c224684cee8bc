// accuracy_plots.h: the plots of the accuracy study (docs/accuracy/*.png), per ior and prism
// mode one figure of a panel per roughness (rows) and theta_i (columns): the retro lobe along and
// across the plane of incidence, and the in-plane slices of the whole BRDF on a log scale.
#pragma once

#include <string>
#include <vector>

#include "study.h"

namespace retroprism::report {

// The file names of the plots of a study grid, in the document's order.
std::vector<std::string> accuracy_plot_names(const sim::StudyGrid& grid);

// Renders every plot into folder `dir`; InputError when one cannot be written.
void write_accuracy_plots(const sim::StudyResults& study, const std::string& dir);

} // namespace retroprism::report
