// libFuzzer target: rpfuzz::check_mtlx (fuzz/fuzz_checks.h) on every input; a violated property
// or an unexpected exception aborts, which libFuzzer reports as a crash.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <typeinfo>

#include "fuzz_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
    try {
        rpfuzz::check_mtlx(data, size);
    } catch (const rpfuzz::Violation& v) {
        std::fprintf(stderr, "VIOLATION: %s\n", v.what());
        std::abort();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "UNEXPECTED EXCEPTION %s: %s\n", typeid(e).name(), e.what());
        std::abort();
    }
    return 0;
}
