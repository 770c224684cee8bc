// text_file.h: a whole file as text, a line without its surrounding blanks and a CSV line's
// fields, for the readers.
#pragma once

#include <string>
#include <vector>

namespace retroprism {

// The bytes of the file at `path`; InputError `<path>: cannot open file` when it cannot be read.
std::string read_text_file(const std::string& path);

// `s` without leading and trailing blanks (space, tab, CR, LF).
std::string trim(const std::string& s);

// The comma-separated fields of `line`, each trimmed; a trailing comma gives an empty last field.
std::vector<std::string> split_csv(const std::string& line);

} // namespace retroprism
