// text_file.h: a whole file as text, for the readers.
#pragma once

#include <string>

namespace retroprism {

// The bytes of the file at `path`; InputError "<path>: cannot open file" when it cannot be read.
std::string read_text_file(const std::string& path);

} // namespace retroprism
