#!/usr/bin/env bash
# Installs the Debian packages (if missing), configures and builds retroprism in build/.
# Idempotent; usable from any folder. BUILD_DIR overrides the build folder.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
bash "$root/scripts/setup-debian.sh"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRETROPRISM_WERROR=ON >/dev/null
ninja -C "$build"
