// standards.h: a material judged against a standard's minimum coefficients of retroreflection:
// `retroprism ra --standard NAME`.
//
// The standards' tables are run-time data (examples/standards/NAME.csv, found through
// util/paths.h's data_path, installed in share/retroprism/examples/standards): R_A tables
// (io/ra_table.h) marked `# kind: minimum`, whose comments cite their source.
//
// Rule: the material's R_A at an entry is the luminance Y of f cos(theta_i) cos(theta_o)
// (analysis/photometry.h, ra_at_entry; a row without rotation is the mean over rotations 0 and
// 90 degrees), its retro_color included as it is: the material is judged as the colour it is
// said to be (`color`), against that colour's rows only. An entry passes when the material's
// R_A is at least the minimum; the material passes when every entry does. Rows without a colour
// (a table without a color column) hold for every colour.
#pragma once

#include <string>
#include <vector>

#include "photometry.h"
#include "prismatic_retroreflector.h"
#include "ra_table.h"

namespace retroprism {

// The bundled tables' names (the stems of examples/standards/*.csv), sorted.
std::vector<std::string> standard_names();

// The bundled table NAME. InputError "--standard NAME: no such standard table; the bundled
// ones: ..." for an unknown name; InputError "FILE: not a table of minimums (...)" for a table
// without `# kind: minimum`; the reader's FILE:LINE errors otherwise.
RaMeasurements read_standard(const std::string& name);

struct StandardEntry {
    RaEntry entry;       // the table's row: its angles and the minimum (entry.ra)
    double material = 0; // the material's R_A there, cd lx^-1 m^-2
    bool pass = false;   // material >= entry.ra
};

struct StandardJudgement {
    std::string color;                  // the colour judged
    std::vector<StandardEntry> entries; // the table's rows of that colour, in file order
    bool pass = false;                  // every entry passes
};

// The material against the table's rows of `color` (one of ra_colors()). InputError naming
// the allowed colours for another name, and "FILE: no rows of colour C; the table's colours:
// ..." when the table lists colours but not this one. R_A over the channels or photopic
// (photometry.h's RaSpectrum).
StandardJudgement judge_standard(const RaMeasurements& table, const Params& material,
                                 const std::string& color = "white",
                                 RaSpectrum spectrum = RaSpectrum::Channels);

} // namespace retroprism
