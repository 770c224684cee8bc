#!/usr/bin/env bash
# The main job on the bundled examples: sets up, builds, renders the example MaterialX document
# under a headlight (out/white_sign.exr with a layer per lobe, out/white_sign.png) and prints
# its R_A table; plots every example material's BRDF slices into out/demo/; fits the node and the
# MaterialX-style GGX to the 3M Diamond Grade 983 R_A table (out/dg983_white_fit.png, the same
# fit as the checked-in preset examples/sheeting/dg983_white.mtlx) and sets the preset against
# that GGX: night previews at the same exposure and the sign's luminance for a driver
# approaching from 300 m to 30 m (out/approach/).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
cli="${BUILD_DIR:-$root/build}/cli/retroprism"
# render writes into an existing folder only; a clean checkout has no out/.
mkdir -p "$root/out"
"$cli" render "$root/examples/documents/white_sign.mtlx" -o "$root/out/white_sign.exr" "$@"
"$cli" demo --materials "$root/examples/materials" --out "$root/out/demo"
sheeting="$root/examples/sheeting"
"$cli" fit --ra "$sheeting/dg983_white.csv" --plot "$root/out/dg983_white_fit.png"
"$cli" approach "$sheeting/dg983_white.mtlx" --table "$sheeting/dg983_white.csv" \
  --out "$root/out/approach"
