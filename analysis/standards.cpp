#include "standards.h"

#include <algorithm>
#include <filesystem>

#include "error.h"
#include "paths.h"
#include "ra_fit.h"

namespace fs = std::filesystem;

namespace retroprism {

namespace {

const char* const kFolder = "examples/standards";

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names)
        s += (s.empty() ? "" : ", ") + n;
    return s;
}

} // namespace

std::vector<std::string> standard_names() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(data_path(kFolder), ec))
        if (e.path().extension() == ".csv") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

RaMeasurements read_standard(const std::string& name) {
    const std::vector<std::string> names = standard_names();
    if (std::find(names.begin(), names.end(), name) == names.end())
        throw InputError("--standard " + name + ": no such standard table; the bundled ones: " +
                         (names.empty() ? "none in " + data_path(kFolder) : joined(names)));
    RaMeasurements t = read_ra_table(data_path(kFolder) + "/" + name + ".csv");
    if (t.kind != RaKind::Minimum)
        throw InputError(t.file + ": not a table of minimums (a standard's table has a comment "
                                  "line \"# kind: minimum\")");
    return t;
}

StandardJudgement judge_standard(const RaMeasurements& table, const Params& material,
                                 const std::string& color, RaSpectrum spectrum) {
    const std::vector<std::string>& colors = ra_colors();
    if (std::find(colors.begin(), colors.end(), color) == colors.end())
        throw InputError("--color " + color + ": not a sheeting colour; expected one of " +
                         joined(colors));
    RaMeasurements rows = table;
    rows.entries.clear();
    for (const RaEntry& e : table.entries)
        if (e.color.empty() || e.color == color) rows.entries.push_back(e);
    if (rows.entries.empty()) rows = ra_color_rows(table, color); // throws, naming the colours
    StandardJudgement j;
    j.color = color;
    const std::vector<double> values = ra_node_values(material, rows.entries, spectrum);
    j.pass = true;
    for (size_t i = 0; i < rows.entries.size(); ++i) {
        StandardEntry s;
        s.entry = rows.entries[i];
        s.material = values[i];
        s.pass = values[i] >= s.entry.ra;
        j.pass = j.pass && s.pass;
        j.entries.push_back(s);
    }
    return j;
}

} // namespace retroprism
