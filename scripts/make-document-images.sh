#!/usr/bin/env bash
# Writes the images the project's MaterialX documents read, with OpenImageIO's oiiotool (text
# with its font renderer, DejaVu Sans from fonts-dejavu-core). Deterministic: rerunning it
# rewrites the same pixels. The files are checked in; run this after changing it.
#  - tests/data/documents/mask.png (64 x 64, 1 channel): 1 over the upper half (v > 0.5 in
#    MaterialX's texture coordinates), 0 below: the [document] tests' mix mask.
#  - examples/documents/sign_legend.png (1024 x 1024, 1 channel): the legend of
#    examples/documents/legend_sign.mtlx: 1 where the dark film is (a border inside the
#    diamond's edge and the word SLOW), 0 where the white sheeting shows.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

oiiotool --pattern constant:color=0 64x64 1 --box:color=1:fill=1 0,0,63,31 -d uint8 \
  --attrib Software "retroprism scripts/make-document-images.sh" \
  -o "$root/tests/data/documents/mask.png"

# The diamond inscribed in the square image touches the midpoints of its edges; the border is
# the band between the diamond inset by 40 and by 90 pixels (along the axes), drawn as nested
# outlines one pixel apart.
size=1024
half=$((size / 2))
lines=()
for inset in $(seq 40 90); do
  r=$((half - inset))
  lines+=(--line:color=1 "$half,$((half - r)),$((half + r)),$half,$half,$((half + r)),$((half - r)),$half,$half,$((half - r))")
done
oiiotool --pattern constant:color=0 ${size}x${size} 1 "${lines[@]}" \
  --text:x=$half:y=$((half + 70)):size=210:font=DejaVuSans-Bold:color=1:xalign=center "SLOW" \
  -d uint8 --attrib Software "retroprism scripts/make-document-images.sh" \
  -o "$root/examples/documents/sign_legend.png"
echo "wrote tests/data/documents/mask.png and examples/documents/sign_legend.png"
