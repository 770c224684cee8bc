// libFuzzer target: rpfuzz::check_openmaterial (fuzz/fuzz_checks_openmaterial.h) on every input
// (fuzz_target.h).
#include "fuzz_checks_openmaterial.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
    return rpfuzz::run_target(rpfuzz::check_openmaterial, data, size);
}
