// text_file.h: a whole file as text, and a line without its surrounding blanks, for the readers.
#pragma once

#include <string>

namespace retroprism {

// The bytes of the file at `path`; InputError `<path>: cannot open file` when it cannot be read.
std::string read_text_file(const std::string& path);

// `s` without leading and trailing blanks (space, tab, CR, LF).
std::string trim(const std::string& s);

} // namespace retroprism
