// ra_fit.h: fitting the node, and the MaterialX-style retroreflective GGX baseline, to a table
// of measured coefficients of retroreflection R_A (io/ra_table.h): `retroprism fit --ra`.
//
//  - Node: the inputs the parameter table declares fittable (fit_table(), the RP_FIT lines of
//    nodes/prismatic_retroreflector_params.def), nothing else: floats and colours (one grey
//    value) are searched in their declared [lo, hi] (logistic coordinates, on a log scale for
//    Log inputs), enums and booleans by trying every value (every combination when there are
//    several; of combinations whose objectives agree within 1e-6 relative, the first in table
//    order). Inputs not fitted keep the base material's values, as do the fittable inputs
//    the caller holds (`retroprism fit --ra --hold NAME,...`). prism_pitch is fitted only when
//    the base has one (diffraction on); a base without a pitch stays geometric optics.
//  - Baseline ("mrm"): baselines::RetroreflectiveGGX, its GGX roughness in [1e-4, 1] (log), ior
//    in [1.01, 3] and specular weight in [0, 1]; its Lambert colour is kept (0.8): at
//    observation angles of a few degrees it adds < 0.3 cd lx^-1 m^-2.
//  - R_A of an entry: luminance Y of f cos(theta_i) cos(theta_o), at its rotation or the mean
//    over rotations 0 and 90 degrees, by analysis/photometry.h (ra_at_entry).
//  - Objective (RaObjective): the mean of (ln m - ln y)^2 over the entries, every entry alike
//    (rms, the default), the largest (ln m - ln y)^2 (max: minimax in the ratio, for a table
//    every entry of which is to be met within a factor; `fit --ra --objective max`), or the
//    largest (m / y - 1)^2 (relative: minimax in the report's error (m - y) / y, for a table
//    every entry of which is to be met within a percentage; `--objective relative`). The
//    minimax objectives are searched from the least-squares optimum, which they keep unless
//    they find lower. Coloured tables' scale s_C (below) then centres the colour's largest and
//    smallest ln m - ln y instead of their mean (max), or makes its largest and smallest m / y
//    equally far from 1 (relative).
//  - Optimiser (deterministic): search_box (util/minimize.h, Nelder-Mead in logistic
//    coordinates, shared with the ALTA fitter) from the base values and from the centre and both
//    sides of each input's range, restarted from the best until it improves by less than 1e-9
//    relative. The fitted values are then rounded to 6 significant digits (a value within 1e-6
//    of its range of a bound to the bound) and
//    the report is that of the rounded values, so that a document written from them gives R_A
//    exactly as reported.
//  - Coloured tables (rows with a `color`, io/ra_table.h; fit_ra_colors): R_A is a luminance,
//    so a table fixes each colour's luminance but not its chromaticity, which comes from the
//    base material. (1) The node is fitted as above to the reference rows: the white rows, or
//    without white rows those of the table's first colour. (2) Per colour C of the table, that
//    geometry is kept and retro_color = s_C chroma_C, where chroma_C is the base's retro_color
//    divided by its luminance Y for the colour returned (the hue the caller gives, e.g.
//    `--material yellow_sign.json --color yellow`; a grey base gives a grey retro_color) and
//    (1, 1, 1) for white and every other colour (their luminance only); s_C makes the mean
//    of ln(model / measured) over C's rows zero (iterations s <- s exp(-mean), R_A being
//    proportional to retro_color but for the specular and diffuse parts), each channel kept in
//    retro_color's fitted range and rounded to 6 significant digits. (3) The result is the
//    material of one colour (default: white if the table has white rows, else its first
//    colour), reported over that colour's rows, with every colour's retro_color and errors.
#pragma once

#include <string>
#include <vector>

#include "baselines.h"
#include "photometry.h"
#include "prismatic_retroreflector.h"
#include "ra_table.h"

namespace retroprism {

enum class RaObjective { Rms, Max, Relative };

// "rms", "max" or "relative"; InputError "--objective NAME: not one of rms, max, relative" for
// any other name.
RaObjective ra_objective(const std::string& name);
const char* ra_objective_name(RaObjective objective);

struct RaFitReport {
    std::vector<double> model; // R_A per entry, cd lx^-1 m^-2
    std::vector<double> error; // (model - measured) / measured per entry
    double log_rms = 0;        // sqrt(mean((ln model - ln measured)^2))
    double max_error = 0;      // max |error|
};

struct RaNodeFit {
    Params params;                   // the base with the fitted inputs
    std::vector<std::string> fitted; // the fitted inputs' names, in table order
    RaFitReport report;
    int evaluations = 0;
};

struct RaMrmFit {
    baselines::RetroreflectiveGGX model;
    RaFitReport report;
    int evaluations = 0;
};

// R_A (Y) of the node built from ra_params(material), over the channels or photopic
// (photometry.h's RaSpectrum), and of the baseline, at every entry.
std::vector<double> ra_node_values(const Params& material, const std::vector<RaEntry>& entries,
                                   RaSpectrum spectrum = RaSpectrum::Channels);
std::vector<double> ra_mrm_values(const baselines::RetroreflectiveGGX& m,
                                  const std::vector<RaEntry>& entries);

RaFitReport ra_fit_report(const RaMeasurements& t, const std::vector<double>& model);

// InputError "FILE: N rows, fewer than the M inputs fitted (...)" when the table has fewer
// entries than fitted inputs. `held`: fittable inputs kept at the base's value instead (names
// of the parameter table's RP_FIT inputs; InputError naming any other).
RaNodeFit fit_ra_node(const RaMeasurements& t, const Params& base = Params(),
                      const std::vector<std::string>& held = {},
                      RaObjective objective = RaObjective::Rms,
                      RaSpectrum spectrum = RaSpectrum::Channels);
RaMrmFit fit_ra_mrm(const RaMeasurements& t, RaObjective objective = RaObjective::Rms);

struct RaColorFit {
    std::string color;  // one of ra_colors()
    Color3 retro_color; // s_C chroma_C, see the top of this header
    bool hue = false;   // chroma_C is the base's hue (the colour returned, not white)
    RaFitReport report; // over the colour's rows
};

struct RaColoredFit {
    RaNodeFit fit;                  // the material of `color`, reported over `rows`
    RaMeasurements rows;            // the table's rows of that colour (the whole table without
                                    // colours)
    std::vector<RaColorFit> colors; // every colour of the table, in table order (none without)
};

// A table without colours: fit_ra_node's fit of the whole table. With colours: the steps at the
// top of this header; `color` names the material returned (empty: the default), InputError
// "FILE: no rows of colour C; the table's colours: ..." for a colour the table has not.
RaColoredFit fit_ra_colors(const RaMeasurements& t, const Params& base = Params(),
                           const std::vector<std::string>& held = {}, const std::string& color = "",
                           RaObjective objective = RaObjective::Rms,
                           RaSpectrum spectrum = RaSpectrum::Channels);

} // namespace retroprism
