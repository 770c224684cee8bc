// ra_print.h: an R_A table as text or CSV (`retroprism ra`, `render`); measured R_A against
// models, entry by entry (`fit --ra`, `ra --table`).
#pragma once

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "photometry.h"
#include "ra_table.h"

namespace retroprism {

// Text: Y (and with `rgb` the R, G, B tables), rows observation, columns entrance angle.
void print_ra_table(const RaTable& t, const std::string& material, bool rgb, std::FILE* out);
// CSV: observation_deg,entrance_deg,rotation_deg,R_A_Y,R_A_R,R_A_G,R_A_B.
void print_ra_csv(const RaTable& t, std::FILE* out);

// One row per entry: its line, angles (rotation "mean": the mean over 0 and 90 degrees),
// measured R_A, then per model its R_A and relative error (model - measured) / measured in %;
// then per model the RMS of ln(model / measured) and the largest |error|.
using RaModelValues = std::pair<std::string, std::vector<double>>; // name, R_A per entry
void print_ra_comparison(const RaMeasurements& t, const std::vector<RaModelValues>& models,
                         std::FILE* out);

} // namespace retroprism
