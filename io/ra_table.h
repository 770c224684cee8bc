// ra_table.h: measured coefficients of retroreflection R_A (cd lx^-1 m^-2), as product bulletins
// and standards tabulate them (ASTM E810, CIE 54.2), in a CSV file: `retroprism fit --ra`.
//
// Form: a header row naming the columns, then one measurement per row; lines whose first
// non-blank character is '#' are comments, blank lines are skipped; fields are separated by
// commas (blanks around them ignored). Columns, in any order, each at most once:
//   observation_deg   observation angle alpha, in (0, 5] degrees             (required)
//   entrance_deg      entrance angle beta, in (-90, 90) degrees              (required)
//   ra                R_A, cd lx^-1 m^-2, > 0                                 (required)
//   rotation_deg      rotation angle epsilon, in [-360, 360] degrees         (optional)
//   presentation_deg  presentation angle gamma, in [-180, 180] degrees       (optional)
//   color             the sheeting's colour, one of ra_colors() (white, yellow, ...)  (optional)
// A row without a rotation angle (no column, or an empty field) is the mean over the rotations
// 0 and 90 degrees (ASTM E810's average for rotation-sensitive prismatic sheeting); without a
// presentation angle it is 0. The angle conventions are analysis/photometry.h's.
//
// Colour: with a `color` column every row names the colour of the sheeting it is for (a field
// from ra_colors(), never empty), and one file may hold rows of several colours (a standard's
// minimums per colour, or one product measured in several colours); rows repeating the angles of
// an earlier row are allowed for another colour. Without the column the rows are of one
// material, colour unstated (RaEntry::color empty).
//
// Kind: a comment line `# kind: minimum` says that the values are minimums a sheeting must reach
// (a standard's table: `retroprism ra --standard`); `# kind: measured`, the default, that they
// are measurements (`fit --ra`). At most one such line per file; any other value is an error.
#pragma once

#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace retroprism {

struct RaEntry {
    double observation_deg = 0;
    double entrance_deg = 0;
    std::optional<double> rotation_deg; // none: the mean over rotations 0 and 90 degrees
    double presentation_deg = 0;
    double ra = 0;     // cd lx^-1 m^-2
    std::string color; // one of ra_colors(), or empty: the table has no colour column
    int line = 0;      // 1-based line in the file
};

// What a table's values are (the `# kind:` comment line).
enum class RaKind { Measured, Minimum };

struct RaMeasurements {
    std::string file;                  // the name used in messages
    std::vector<std::string> comments; // the comment lines, without '#' and leading blanks
    std::vector<RaEntry> entries;      // in file order, at least one
    RaKind kind = RaKind::Measured;
};

// The columns a table may have, in the order above.
const std::vector<std::string>& ra_columns();

// The sheeting colours a `color` field may name: white, yellow, orange, green, red, blue, brown,
// grey, fluorescent_yellow, fluorescent_yellow_green, fluorescent_orange, fluorescent_red,
// fluorescent_pink.
const std::vector<std::string>& ra_colors();

// The colours of a table's rows, each once, in the order of their first row (none without a
// colour column).
std::vector<std::string> ra_table_colors(const RaMeasurements& t);

// The rows of one colour (comments, kind and file kept); InputError "FILE: no rows of colour
// C; the table's colours: ..." when there are none.
RaMeasurements ra_color_rows(const RaMeasurements& t, const std::string& color);

// Reads and checks a table; every error is an InputError "FILE:LINE: ..." naming the column
// (by name and 1-based position), the value and the allowed form or range: no header row, an
// unknown, repeated or missing column, a row with another number of fields than the header, a
// field that is not a finite number, a value outside its range, a row repeating the angles of
// an earlier one (naming that line), a colour not in ra_colors() (listing them), a `# kind:`
// line with another value than measured or minimum or a second such line, a file without rows.
RaMeasurements parse_ra_table(std::istream& in, const std::string& name);
RaMeasurements read_ra_table(const std::string& path);

} // namespace retroprism
