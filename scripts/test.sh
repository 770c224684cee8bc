#!/usr/bin/env bash
# The tests: sets up, builds (warnings are errors), checks formatting, then runs the tests
# through ctest, one per core at a time, all but the long sweeps (ctest label "ci", which
# .ci/run runs after this; `bash scripts/test.sh -L ci` runs them alone).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
bash "$root/scripts/build.sh"
bash "$root/scripts/check-format.sh"
cd "$build"
if [ $# -eq 0 ]; then set -- -LE '^(ci|release)$'; fi
ctest --output-on-failure --timeout 1200 -j "$(nproc)" "$@"
