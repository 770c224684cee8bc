#!/usr/bin/env bash
# ThreadSanitizer build of the test binaries that hold the multithreaded paths, in build-tsan/
# (-O1 -g -fsanitize=thread), then only their test cases tagged [threads]: batches across cores
# (nodes/batch.h), util's parallel_for and parallel_ranges, the simulator, the fitter and the
# night preview renderer. Any report fails (halt_on_error). No Python module, and only these
# binaries (and what they depend on) are built, to keep CI's time. Arguments go to each test
# binary after the tag (e.g. -s). BUILD_DIR overrides the build folder.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build-tsan}"
bash "$root/scripts/setup-debian.sh"

# RP_NO_FORCED_INLINE: the core's calls stay calls (nodes/prism_core.h, nodes/batch.cpp), as in
# the other sanitizer builds.
flags="-fsanitize=thread -fno-omit-frame-pointer"
# -O1 -g1: line tables only, all that TSan's reports need to name the lines, and the build stays
# short (nodes/batch.cpp compiled in 22 s instead of 69 s with full debug information, -g).
# -Wmaybe-uninitialized is not an error here (GCC 12 reports it falsely at -O1 in code the
# normal build checks).
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DRETROPRISM_WERROR=ON \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DCMAKE_CXX_FLAGS="$flags -Wno-maybe-uninitialized -DRP_NO_FORCED_INLINE" \
  -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags" \
  -DRETROPRISM_PYTHON=OFF >/dev/null
binaries="batch util sim photometry physics"
targets=""
for b in $binaries; do targets="$targets retroprism_test_$b"; done
# shellcheck disable=SC2086
ninja -C "$build" $targets

export TSAN_OPTIONS="halt_on_error=1:abort_on_error=1:second_deadlock_stack=1:suppressions=$root/scripts/tsan.supp"
for b in $binaries; do
  echo "tsan: retroprism_test_$b [threads]"
  "$build/tests/retroprism_test_$b" "[threads]" "$@"
done
echo "tsan: no report"
