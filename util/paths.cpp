#include "paths.h"

#include <cstdlib>
#include <filesystem>

#include "error.h"

namespace fs = std::filesystem;

namespace retroprism {

namespace {

// The file whose presence marks a data folder.
constexpr const char* kMarker = "materialx/tools/mx.cjs";

bool holds_data(const fs::path& dir) {
    std::error_code ec;
    return fs::is_regular_file(dir / kMarker, ec);
}

} // namespace

std::string executable_dir() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::current_path().string() : exe.parent_path().string();
}

std::string data_dir() {
    if (const char* env = std::getenv("RETROPRISM_DATA_DIR"); env && *env) {
        if (!holds_data(env))
            throw InputError(std::string("RETROPRISM_DATA_DIR=") + env + ": no " + kMarker +
                             " there");
        return fs::path(env).lexically_normal().string();
    }
    const fs::path exe = executable_dir();
    const fs::path installed = exe / ".." / "share" / "retroprism";
    if (holds_data(installed)) return installed.lexically_normal().string();
    for (fs::path dir = exe; !dir.empty(); dir = dir.parent_path()) {
        if (holds_data(dir)) return dir.string();
        if (dir == dir.parent_path()) break;
    }
    throw InputError("run-time data not found: no " + std::string(kMarker) + " in " +
                     installed.lexically_normal().string() + " nor in a folder above " +
                     exe.string() + " (set RETROPRISM_DATA_DIR to the folder that holds it)");
}

std::string data_path(const std::string& relative) {
    return data_dir() + "/" + relative;
}

} // namespace retroprism
