// parse.h: the one number parser of the project. Every number a user types (options, CSV and
// table cells) is read here, so every such error reads the same way.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace retroprism {

// The whole of `text` as a finite double, or nothing (empty text, trailing characters,
// overflow to infinity, NaN). With finiteOnly false, "nan" and "inf" (any sign, as printf
// writes them) are numbers too.
std::optional<double> try_parse_number(const std::string& text, bool finiteOnly = true);

// `v` as messages and reports write it: 6 significant digits, as printf's %g and an ostream's
// default (0.1, 1e+30, inf, nan).
std::string number_text(double v);

// The whole of `text` as a finite double; otherwise an InputError `<what> <text>: expected a
// finite number`.
double parse_number(const std::string& text, const std::string& what);

// The whole of `text` as a number within [lo, hi]; otherwise an InputError `<what> <text>:
// expected a number in [lo, hi]`.
double parse_number_in(const std::string& text, const std::string& what, double lo, double hi);

// The comma-separated numbers of `text` (an option's list, "0.1,0.2,1"), each as parse_number
// reads it (lo and hi infinite: any finite number) or parse_number_in; the InputError names the
// list and its bad item (`<what> <text>: <item>: expected ...`; one item: `<what> <item>:
// expected ...`).
std::vector<double> parse_number_list(const std::string& text, const std::string& what,
                                      double lo = -std::numeric_limits<double>::infinity(),
                                      double hi = std::numeric_limits<double>::infinity());

// A whole number within [lo, hi] (written as an integer or in exponent form, 4e6); otherwise
// an InputError `<what> <text>: expected a whole number in [lo, hi]`.
std::uint64_t parse_count(const std::string& text, const std::string& what, double lo, double hi);

} // namespace retroprism
