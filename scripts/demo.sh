#!/usr/bin/env bash
# The main job on the bundled examples: sets up, builds, then writes BRDF slice plots (PNG)
# and per-lobe EXR maps of every material in examples/materials to out/demo/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
"${BUILD_DIR:-$root/build}/cli/retroprism" demo --materials "$root/examples/materials" --out "$root/out/demo" "$@"
