#include "text_file.h"

#include <fstream>
#include <sstream>

#include "error.h"

namespace retroprism {

std::string read_text_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open file");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

} // namespace retroprism
