// ra_print.h: an R_A table as text or CSV (`retroprism ra`, `render`).
#pragma once

#include <cstdio>
#include <string>

#include "photometry.h"

namespace retroprism {

// Text: Y (and with `rgb` the R, G, B tables), rows observation, columns entrance angle.
void print_ra_table(const RaTable& t, const std::string& material, bool rgb, std::FILE* out);
// CSV: observation_deg,entrance_deg,rotation_deg,R_A_Y,R_A_R,R_A_G,R_A_B.
void print_ra_csv(const RaTable& t, std::FILE* out);

} // namespace retroprism
