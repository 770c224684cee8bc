// fuzz_target.h: the body every libFuzzer target of fuzz/ shares: one of the checks of
// fuzz_checks.h on the input; a violated property or an unexpected exception prints what it was
// and aborts, which libFuzzer reports as a crash (and keeps the input).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <typeinfo>

#include "fuzz_checks.h"

namespace rpfuzz {

inline int run_target(void (*check)(const std::uint8_t*, size_t), const std::uint8_t* data,
                      size_t size) {
    try {
        check(data, size);
    } catch (const Violation& v) {
        std::fprintf(stderr, "VIOLATION: %s\n", v.what());
        std::abort();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "UNEXPECTED EXCEPTION %s: %s\n", typeid(e).name(), e.what());
        std::abort();
    }
    return 0;
}

} // namespace rpfuzz
