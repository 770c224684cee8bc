#!/usr/bin/env bash
# The main job on the bundled example: sets up, builds, renders the example MaterialX document
# under a headlight (out/white_sign.exr with a layer per lobe, out/white_sign.png) and prints
# its R_A table; then plots every example material's BRDF slices into out/demo/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
cli="${BUILD_DIR:-$root/build}/cli/retroprism"
# render writes into an existing folder only; a clean checkout has no out/.
mkdir -p "$root/out"
"$cli" render "$root/examples/documents/white_sign.mtlx" -o "$root/out/white_sign.exr" "$@"
"$cli" demo --materials "$root/examples/materials" --out "$root/out/demo"
