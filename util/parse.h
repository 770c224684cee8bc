// parse.h: the one number parser of the project. Every number a user types (options, CSV and
// table cells) is read here, so every such error reads the same way.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

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

// A whole number within [lo, hi] (written as an integer or in exponent form, 4e6); otherwise
// an InputError `<what> <text>: expected a whole number in [lo, hi]`.
std::uint64_t parse_count(const std::string& text, const std::string& what, double lo, double hi);

} // namespace retroprism
