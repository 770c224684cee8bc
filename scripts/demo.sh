#!/usr/bin/env bash
# The main job on the bundled examples: sets up, builds, renders the bundled sign document under
# a headlight through MaterialX's shader (its legend a dark film mixed with the white sheeting
# through an image, under a clear overlay: out/legend_sign.exr with a layer per lobe and the
# rest of the graph, out/legend_sign.png) and prints its sheeting's R_A table (white_sign.mtlx);
# plots every example material's BRDF slices into out/demo/; fits the node and the
# MaterialX-style GGX to the 3M Diamond Grade 983 R_A table (out/dg983_white_fit.png, the same
# fit as the checked-in preset examples/sheeting/dg983_white.mtlx) and sets the preset against
# that GGX: night previews at the same exposure and the sign's luminance for a driver
# approaching from 300 m to 30 m (out/approach/), then the same for the preset with diffraction
# (examples/sheeting/dg983_white_tir.mtlx); and the preset under two low beams from a
# photometric file, the synthetic one of examples/headlamps/, beside the luminance a driver needs
# (out/approach_headlamps/).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
cli="${BUILD_DIR:-$root/build}/cli/retroprism"
# render writes into an existing folder only; a clean checkout has no out/.
mkdir -p "$root/out"
"$cli" render "$root/examples/documents/legend_sign.mtlx" -o "$root/out/legend_sign.exr" "$@"
"$cli" ra --document "$root/examples/documents/white_sign.mtlx"
"$cli" demo --materials "$root/examples/materials" --out "$root/out/demo"
sheeting="$root/examples/sheeting"
"$cli" fit --ra "$sheeting/dg983_white.csv" --hold dihedral_spread --plot "$root/out/dg983_white_fit.png"
"$cli" approach "$sheeting/dg983_white.mtlx" --table "$sheeting/dg983_white.csv" \
  --out "$root/out/approach"
# The same table's preset with diffraction (uncoated prisms, their pitch fitted: 135 um): on approach it
# keeps its light at 1 degree of observation, where the geometric preset goes dark.
"$cli" approach "$sheeting/dg983_white_tir.mtlx" --table "$sheeting/dg983_white.csv" \
  --out "$root/out/approach"
# Two headlamps from a photometric file (the synthetic low beam), a car, a shoulder sign.
"$cli" approach "$sheeting/dg983_white.mtlx" --table "$sheeting/dg983_white.csv" \
  --headlamps "$root/examples/headlamps/synthetic_low_beam.ies" --out "$root/out/approach_headlamps"
