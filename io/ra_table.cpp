#include "ra_table.h"

#include <algorithm>
#include <sstream>

#include "error.h"
#include "parse.h"
#include "text_file.h"

namespace retroprism {

namespace {

enum Column { kObservation, kEntrance, kRa, kRotation, kPresentation, kColor, kColumnCount };

struct Range {
    double lo, hi;
    bool openLo, openHi;
    const char* what;
};

// The allowed values per numeric column (in ra_columns() order; the colour is a name).
const Range kRanges[kColor] = {
    {0.0, 5.0, true, false, "an observation angle in (0, 5] degrees"},
    {-90.0, 90.0, true, true, "an entrance angle in (-90, 90) degrees"},
    {0.0, 1e300, true, false, "an R_A in cd lx^-1 m^-2 greater than 0"},
    {-360.0, 360.0, false, false, "a rotation angle in [-360, 360] degrees"},
    {-180.0, 180.0, false, false, "a presentation angle in [-180, 180] degrees"},
};

const char* const kForm =
    "observation_deg,entrance_deg,ra[,rotation_deg][,presentation_deg][,color]";

bool in_range(double v, const Range& r) {
    return (r.openLo ? v > r.lo : v >= r.lo) && (r.openHi ? v < r.hi : v <= r.hi);
}

// The header row: the column of each field (every required one present, none repeated).
std::vector<int> header_columns(const std::vector<std::string>& fields, const std::string& at) {
    std::vector<int> cols;
    const std::vector<std::string>& names = ra_columns();
    for (size_t k = 0; k < fields.size(); ++k) {
        const auto it = std::find(names.begin(), names.end(), fields[k]);
        const std::string col = "column " + std::to_string(k + 1);
        if (it == names.end())
            throw InputError(at + ", " + col + ": unknown column \"" + fields[k] +
                             "\"; expected a header row " + kForm);
        const int c = int(it - names.begin());
        if (std::find(cols.begin(), cols.end(), c) != cols.end())
            throw InputError(at + ", " + col + ": column \"" + fields[k] +
                             "\" appears twice; expected a header row " + kForm);
        cols.push_back(c);
    }
    for (int c : {kObservation, kEntrance, kRa})
        if (std::find(cols.begin(), cols.end(), c) == cols.end())
            throw InputError(at + ": the header row has no column " + names[size_t(c)] +
                             "; expected " + kForm);
    return cols;
}

std::string list_text(const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names)
        s += (s.empty() ? "" : ", ") + n;
    return s;
}

std::string key_text(const RaEntry& e) {
    std::ostringstream ss;
    if (!e.color.empty()) ss << "colour " << e.color << ", ";
    ss << "observation " << e.observation_deg << ", entrance " << e.entrance_deg << ", rotation "
       << (e.rotation_deg ? std::to_string(*e.rotation_deg) : std::string("mean of 0 and 90"))
       << ", presentation " << e.presentation_deg;
    return ss.str();
}

bool same_angles(const RaEntry& a, const RaEntry& b) {
    return a.observation_deg == b.observation_deg && a.entrance_deg == b.entrance_deg &&
           a.rotation_deg == b.rotation_deg && a.presentation_deg == b.presentation_deg &&
           a.color == b.color;
}

std::string color_field(const std::string& field, const std::string& where) {
    const std::vector<std::string>& colors = ra_colors();
    if (std::find(colors.begin(), colors.end(), field) == colors.end())
        throw InputError(where + ": \"" + field + "\" is not a sheeting colour; expected one of " +
                         list_text(colors));
    return field;
}

// A `# kind: VALUE` comment line: sets t.kind (once per file).
void kind_directive(const std::string& comment, RaMeasurements& t, bool& seen,
                    const std::string& at) {
    if (comment.compare(0, 5, "kind:") != 0) return;
    const std::string value = trim(comment.substr(5));
    if (seen) throw InputError(at + ": a second \"# kind:\" line; expected at most one per file");
    seen = true;
    if (value == "measured")
        t.kind = RaKind::Measured;
    else if (value == "minimum")
        t.kind = RaKind::Minimum;
    else
        throw InputError(at + ": \"# kind: " + value +
                         "\" is not a kind of table; expected measured or minimum");
}

RaEntry parse_row(const std::vector<std::string>& fields, const std::vector<int>& cols,
                  const std::string& at) {
    const std::vector<std::string>& names = ra_columns();
    if (fields.size() != cols.size())
        throw InputError(at + ": " + std::to_string(fields.size()) +
                         " fields, but the header row " + "has " + std::to_string(cols.size()) +
                         " columns");
    RaEntry e;
    for (size_t k = 0; k < fields.size(); ++k) {
        const int c = cols[k];
        const std::string where =
            at + ", column " + std::to_string(k + 1) + " (" + names[size_t(c)] + ")";
        if (fields[k].empty() && c == kRotation) continue; // the mean over 0 and 90 degrees
        if (c == kColor) {
            e.color = color_field(fields[k], where);
            continue;
        }
        const std::optional<double> v = try_parse_number(fields[k]);
        if (!v)
            throw InputError(where + ": \"" + fields[k] + "\" is not a number; expected " +
                             kRanges[c].what);
        if (!in_range(*v, kRanges[c]))
            throw InputError(where + ": " + fields[k] + " is out of range; expected " +
                             kRanges[c].what);
        switch (c) {
        case kObservation:
            e.observation_deg = *v;
            break;
        case kEntrance:
            e.entrance_deg = *v;
            break;
        case kRa:
            e.ra = *v;
            break;
        case kRotation:
            e.rotation_deg = *v;
            break;
        default:
            e.presentation_deg = *v;
            break;
        }
    }
    return e;
}

} // namespace

const std::vector<std::string>& ra_columns() {
    static const std::vector<std::string> v = {"observation_deg", "entrance_deg",     "ra",
                                               "rotation_deg",    "presentation_deg", "color"};
    return v;
}

const std::vector<std::string>& ra_colors() {
    static const std::vector<std::string> v = {"white",
                                               "yellow",
                                               "orange",
                                               "green",
                                               "red",
                                               "blue",
                                               "brown",
                                               "grey",
                                               "fluorescent_yellow",
                                               "fluorescent_yellow_green",
                                               "fluorescent_orange",
                                               "fluorescent_red",
                                               "fluorescent_pink"};
    return v;
}

std::vector<std::string> ra_table_colors(const RaMeasurements& t) {
    std::vector<std::string> out;
    for (const RaEntry& e : t.entries)
        if (!e.color.empty() && std::find(out.begin(), out.end(), e.color) == out.end())
            out.push_back(e.color);
    return out;
}

RaMeasurements ra_color_rows(const RaMeasurements& t, const std::string& color) {
    RaMeasurements out = t;
    out.entries.clear();
    for (const RaEntry& e : t.entries)
        if (e.color == color) out.entries.push_back(e);
    if (out.entries.empty())
        throw InputError(t.file + ": no rows of colour " + color + "; the table's colours: " +
                         (ra_table_colors(t).empty() ? std::string("none (no color column)")
                                                     : list_text(ra_table_colors(t))));
    return out;
}

RaMeasurements parse_ra_table(std::istream& in, const std::string& name) {
    RaMeasurements t;
    t.file = name;
    std::vector<int> cols;
    std::string raw;
    int lineNo = 0;
    bool kindSeen = false;
    while (std::getline(in, raw)) {
        ++lineNo;
        const std::string at = name + ":" + std::to_string(lineNo);
        if (lineNo == 1 && raw.compare(0, 3, "\xEF\xBB\xBF") == 0) raw.erase(0, 3); // UTF-8 BOM
        const std::string line = trim(raw);
        if (line.empty()) continue;
        if (line[0] == '#') {
            t.comments.push_back(trim(line.substr(1)));
            kind_directive(t.comments.back(), t, kindSeen, at);
            continue;
        }
        const std::vector<std::string> fields = split_csv(line);
        if (cols.empty()) {
            cols = header_columns(fields, at);
            continue;
        }
        RaEntry e = parse_row(fields, cols, at);
        e.line = lineNo;
        for (const RaEntry& prev : t.entries)
            if (same_angles(prev, e))
                throw InputError(at + ": a second row for " + key_text(e) + " (the first is line " +
                                 std::to_string(prev.line) + "); expected one measurement per row");
        t.entries.push_back(e);
    }
    if (t.entries.empty())
        throw InputError(name + ":" + std::to_string(std::max(lineNo, 1)) +
                         (cols.empty() ? ": no header row; expected a header row " +
                                             std::string(kForm) + " and one row per measurement"
                                       : std::string(": no rows; expected one row per "
                                                     "measurement after the header row")));
    return t;
}

RaMeasurements read_ra_table(const std::string& path) {
    std::istringstream in(read_text_file(path));
    return parse_ra_table(in, path);
}

} // namespace retroprism
