// ra_print.h: an R_A table as text or CSV (`retroprism ra`, `render`); measured R_A against
// models, entry by entry (`fit --ra`, `ra --table`); a material against a standard's minimums
// (`ra --standard`); the colours of a coloured table's fit (`fit --ra`).
#pragma once

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "photometry.h"
#include "ra_fit.h"
#include "ra_table.h"
#include "standards.h"

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

// The bundled standards, one line each: its name and its table's first comment line.
void print_standard_list(std::FILE* out);

// One row per entry of the judged colour: its line, angles, the minimum, the material's R_A,
// the margin (material / minimum - 1) in % and pass or FAIL; then one line "NAME, colour C:
// pass (N of N entries at or above the minimum)" or "FAIL (...)".
void print_standard_judgement(const std::string& name, const StandardJudgement& j,
                              const std::string& material, std::FILE* out);

// A coloured table's fit (ra_fit.h): per colour its retro_color (grey for the colours other than
// white and the one fitted: their luminance) and the fit of its rows.
void print_ra_color_fits(const std::vector<RaColorFit>& colors, std::FILE* out);

// A fitted input's value as fit --ra prints it: a float to 6 digits, a colour as "V (grey)" or
// "(R, G, B)", an enum by its name, a boolean as true or false.
std::string ra_fit_input_text(const Params& p, const std::string& name);

// The comment of the MaterialX document `fit --ra --mtlx` writes: the table's name and
// comments, the fitted inputs, and the node's fit and error at every entry and the baseline's.
std::vector<std::string> ra_fit_document_comment(const RaMeasurements& t, const RaNodeFit& nf,
                                                 const RaMrmFit& mf);

} // namespace retroprism
