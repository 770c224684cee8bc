#!/usr/bin/env bash
# The house rules of docs/ARCHITECTURE.md that a machine can check, over the files git tracks:
#  - no hand-written function longer than 150 lines (universal-ctags' start and end lines;
#    generated files under nodes/generated/ and the OSL of osl/shaders/ are left out);
#  - no library folder names cli/ (nothing below the command line reaches into it);
#  - no source path compiled in: RP_SOURCE_DIR appears in tests/ only;
#  - no test includes a .cpp file;
#  - cli/ holds at most 3,000 lines.
# Prints each violation and fails when there is one.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
max_function=150
max_cli=3000
libraries="nodes util io glsl_gen backends sim analysis report bench python web osl"
status=0

sources=$(git ls-files '*.cpp' '*.h' '*.inc' | grep -v -e '^nodes/generated/' -e '^osl/shaders/' || true)
# Debian's universal-ctags installs ctags-universal (and ctags through the alternatives system).
ctags_bin=$(command -v ctags-universal || command -v ctags)
# shellcheck disable=SC2086
long=$("$ctags_bin" --languages=C++ --c++-kinds=f --fields=+ne -o - $sources |
  awk -F'\t' -v max="$max_function" '{
    start = 0; end = 0
    for (i = 4; i <= NF; ++i) {
      if ($i ~ /^line:/) start = substr($i, 6)
      if ($i ~ /^end:/) end = substr($i, 5)
    }
    if (start > 0 && end > 0 && end - start + 1 > max)
      printf "%s:%d: %s is %d lines (at most %d)\n", $2, start, $1, end - start + 1, max
  }')
if [ -n "$long" ]; then echo "$long"; status=1; fi

# shellcheck disable=SC2086
if grep -rn 'cli/' $libraries; then
  echo "layout: a library names cli/ (libraries never depend on the command line)"
  status=1
fi
if git grep -n RP_SOURCE_DIR -- '*.cpp' '*.h' '*.inc' '*.in' '*CMakeLists.txt' ':!tests/'; then
  echo "layout: RP_SOURCE_DIR outside tests/ (run-time data is found by util/paths.h)"
  status=1
fi
if git grep -nE '#include ".*\.cpp"' -- tests/; then
  echo "layout: a test includes a .cpp file (tests link the libraries)"
  status=1
fi
cli_lines=$(git ls-files cli | xargs cat | wc -l)
if [ "$cli_lines" -gt "$max_cli" ]; then
  echo "layout: cli/ has $cli_lines lines (at most $max_cli)"
  status=1
fi
if [ "$status" -eq 0 ]; then
  echo "layout: $(echo "$sources" | wc -w) sources, no function over $max_function lines," \
    "no library on cli/, no source path compiled in, cli/ $cli_lines lines"
fi
exit "$status"
