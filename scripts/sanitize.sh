#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build of the library, the CLI and the unit tests
# in build-asan/ (RelWithDebInfo at -O1 -g1, -fsanitize=address,undefined -fno-sanitize-recover=all
# -fno-omit-frame-pointer), then the tests through ctest there. Any sanitizer report fails:
# ASan and UBSan abort the process at the first one, LeakSanitizer makes the process exit
# non-zero; ctest then reports the test as failed. scripts/lsan.supp suppresses leaks in
# third-party libraries only (Mesa's EGL/llvmpipe, LLVM, ...), each entry commented.
# Without arguments every test entry runs but the docs site (Sphinx and Doxygen; its command
# blocks run the same CLI paths as the `cli` entry), `materialx` (its time, 110 s here, is
# MaterialX's own JavaScript, glslang and Mesa; the code of ours it runs, the document writer,
# the C++ reference and the render runner, runs instrumented in `document` and in stress_ci's
# materialx sweep) and the long accuracy sweeps `wave_ci`, `glsl_ci`, `lidar_ci` and
# `photometry_ci` (the standards' fits), which repeat with more points or fits the code paths
# their fast entries run here: the adversarial sweep
# `stress_ci` stays, its inputs being the ones the sanitizers are for. Arguments go to ctest
# instead (e.g. -R cli). BUILD_DIR overrides the build folder.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build-asan}"
bash "$root/scripts/setup-debian.sh"

flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
# Warnings stay errors, except -Wmaybe-uninitialized: with -fsanitize=address GCC 12 reports
# it falsely inside libstdc++'s <regex> (std::function moved in _NFA::_M_insert_subexpr_begin),
# which backends/mx_night.cpp uses; the normal build (scripts/build.sh) keeps it an error.
# No Python module here: an instrumented extension cannot load into Debian's uninstrumented
# python3 (ASan's runtime must come first), and so neither the `python` nor the `install` entry
# (whose consumer links the instrumented libraries without the runtime) exists in this build.
# RP_NO_FORCED_INLINE: the core's calls stay calls (nodes/prism_core.h) and the batch kernels
# call the core instead of inlining all of it (nodes/batch.cpp): instrumented, batch.cpp alone
# took 6.5 min to compile with them inlined, 11 s without.
# -g1: line tables only, all that the reports' stack traces need (file, line, function); with
# full debug information (-g) the instrumented build took 793 s instead of 569 s. -O1: the build
# takes 29% less compiler time than at -O2 (1227 against 1729 CPU seconds), and the instrumented
# tests ran as fast (physics 150 s against 160, sim 166 against 160, photometry 221 against 199,
# chi2 135 against 139, the sanitizers' own checks dominating their time).
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRETROPRISM_WERROR=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DCMAKE_CXX_FLAGS="$flags -Wno-maybe-uninitialized -DRP_NO_FORCED_INLINE" -DCMAKE_EXE_LINKER_FLAGS="$flags" \
  -DCMAKE_SHARED_LINKER_FLAGS="$flags" -DRETROPRISM_PYTHON=OFF >/dev/null
ninja -C "$build"

export ASAN_OPTIONS="abort_on_error=1:halt_on_error=1:detect_leaks=1:strict_init_order=1:check_initialization_order=1:detect_stack_use_after_return=1:symbolize=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:symbolize=1"
export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=1"
if command -v llvm-symbolizer >/dev/null 2>&1; then
  export ASAN_SYMBOLIZER_PATH="$(command -v llvm-symbolizer)"
fi

cd "$build"
if [ $# -eq 0 ]; then set -- -LE docs -E '^((wave|glsl|lidar|photometry)_ci|materialx)$'; fi
ctest --output-on-failure --timeout 3600 -j2 "$@"
