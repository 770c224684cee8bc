#!/usr/bin/env bash
# Fails when a C++ source differs from what clang-format (with .clang-format) makes of it.
# Generated files are left out (the tables; osl/shaders/, OSL source).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
files=$(git ls-files '*.cpp' '*.h' '*.inc' | grep -v -e '^nodes/generated/' -e '^osl/shaders/' || true)
if [ -z "$files" ]; then exit 0; fi
# shellcheck disable=SC2086
clang-format --dry-run -Werror $files
echo "format: $(echo "$files" | wc -w) files match .clang-format"
