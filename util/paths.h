// paths.h: where the run-time data is (the MaterialX library and tool, example documents and
// materials, the accuracy study's results). No path of the source tree is compiled in: the data
// folder is, in order,
//   1. $RETROPRISM_DATA_DIR, when set (it must hold the data, or it is an error);
//   2. `<exe>/../share/retroprism`, the installed layout;
//   3. the nearest folder above the executable that holds materialx/tools/mx.cjs (a build tree
//      inside the checkout finds the checkout).
#pragma once

#include <string>

namespace retroprism {

// The folder of the running executable (/proc/self/exe).
std::string executable_dir();

// The run-time data folder by the rules above; InputError naming every place tried when none
// holds the data.
std::string data_dir();

// data_dir() + "/" + relative.
std::string data_path(const std::string& relative);

} // namespace retroprism
