// libFuzzer target: rpfuzz::check_luminaire (fuzz/fuzz_checks_luminaire.h) on every input
// (fuzz_target.h): byte 0 picks IES, EULUMDAT or CSV, the rest is the file.
#include "fuzz_checks_luminaire.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
    return rpfuzz::run_target(rpfuzz::check_luminaire, data, size);
}
