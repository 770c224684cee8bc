#include "parse.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "error.h"

namespace retroprism {

std::string number_text(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

std::optional<double> try_parse_number(const std::string& text, bool finiteOnly) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || (finiteOnly && !std::isfinite(v))) return std::nullopt;
    return v;
}

double parse_number(const std::string& text, const std::string& what) {
    const std::optional<double> v = try_parse_number(text);
    if (!v) throw InputError(what + " " + text + ": expected a finite number");
    return *v;
}

double parse_number_in(const std::string& text, const std::string& what, double lo, double hi) {
    const std::optional<double> v = try_parse_number(text);
    if (!v || *v < lo || *v > hi)
        throw InputError(what + " " + text + ": expected a number in [" + number_text(lo) + ", " +
                         number_text(hi) + "]");
    return *v;
}

std::vector<double> parse_number_list(const std::string& text, const std::string& what, double lo,
                                      double hi) {
    const bool one = text.find(',') == std::string::npos;
    const std::string where = one ? what : what + " " + text + ":";
    const bool any = std::isinf(lo) && std::isinf(hi);
    std::vector<double> list;
    for (size_t start = 0; start <= text.size();) {
        const size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        list.push_back(any ? parse_number(item, where) : parse_number_in(item, where, lo, hi));
        start = comma + 1;
    }
    return list;
}

std::uint64_t parse_count(const std::string& text, const std::string& what, double lo, double hi) {
    const std::optional<double> v = try_parse_number(text);
    if (!v || *v != std::floor(*v) || *v < lo || *v > hi) {
        char range[96];
        std::snprintf(range, sizeof range, "[%.0f, %.0f]", lo, hi);
        throw InputError(what + " " + text + ": expected a whole number in " + range);
    }
    return std::uint64_t(*v);
}

} // namespace retroprism
