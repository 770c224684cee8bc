#!/usr/bin/env bash
# The tests: sets up, builds (warnings are errors), checks formatting, then runs every test
# through ctest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
bash "$root/scripts/build.sh"
bash "$root/scripts/check-format.sh"
cd "$build"
ctest --output-on-failure --timeout 1200 "$@"
