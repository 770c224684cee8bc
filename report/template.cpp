// template.cpp: named-placeholder substitution (see template.h).
#include "template.h"

#include "error.h"

namespace retroprism::report {

std::string fill_template(const std::string& tmpl, const TemplateValues& values,
                          const std::string& where) {
    std::string out;
    size_t pos = 0;
    while (true) {
        const size_t open = tmpl.find("{{", pos);
        if (open == std::string::npos) break;
        out.append(tmpl, pos, open - pos);
        const size_t close = tmpl.find("}}", open);
        if (close == std::string::npos)
            throw InputError(where + ": unclosed placeholder after '" + tmpl.substr(open, 30) +
                             "'");
        const std::string tag = tmpl.substr(open + 2, close - open - 2);
        pos = close + 2;
        if (tag.empty() || (tag[0] != '?' && tag[0] != '^')) {
            const auto it = values.text.find(tag);
            if (it == values.text.end())
                throw InputError(where + ": no value for the placeholder {{" + tag + "}}");
            out += it->second;
            continue;
        }
        const std::string name = tag.substr(1), end = "{{/" + name + "}}";
        // A section tag alone on its line takes the line with it.
        if (pos < tmpl.size() && tmpl[pos] == '\n' && (open == 0 || tmpl[open - 1] == '\n')) ++pos;
        const size_t stop = tmpl.find(end, pos);
        const auto flag = values.flags.find(name);
        if (stop == std::string::npos)
            throw InputError(where + ": the section {{" + tag + "}} is not closed by " + end);
        if (flag == values.flags.end())
            throw InputError(where + ": no flag for the section {{" + tag + "}}");
        if (flag->second == (tag[0] == '?'))
            out += fill_template(tmpl.substr(pos, stop - pos), values, where);
        pos = stop + end.size();
        if (pos < tmpl.size() && tmpl[pos] == '\n' && (stop == 0 || tmpl[stop - 1] == '\n')) ++pos;
    }
    out.append(tmpl, pos, std::string::npos);
    return out;
}

} // namespace retroprism::report
