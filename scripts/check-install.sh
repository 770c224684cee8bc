#!/usr/bin/env bash
# The installed tree works alone (issue 17). Installs into a temporary prefix, takes away what
# the installed files could lean on, then runs scripts/verify-install.py on the prefix (the
# command's eval, era, ra, export and check --backend materialx, which needs the installed
# MaterialX tool; view with the installed page, server and baseline GLSL; the consumer example through CMake and pkg-config; the Python module against
# the command, bit for bit).
#   check-install.sh BUILD_DIR      installs the built tree BUILD_DIR and moves the prefix to
#                                   another folder before using it, and checks that no installed
#                                   binary names this checkout (ctest entry "install")
#   check-install.sh --fresh-clone  clones this checkout's HEAD, configures, builds and installs
#                                   it, deletes the clone and its build tree, then also checks
#                                   that no installed binary names the clone (ctest entry
#                                   "install_ci", label release: a full build)
# PYTHON names the interpreter of the Python module (default: Debian's /usr/bin/python3).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
python="${PYTHON:-/usr/bin/python3}"
if [ $# -ne 1 ]; then
  echo "usage: check-install.sh BUILD_DIR | --fresh-clone" >&2
  exit 2
fi
work="$(mktemp -d "${TMPDIR:-/tmp}/retroprism-install.XXXXXX")"
trap 'rm -rf "$work"' EXIT
# The verifier itself is copied out: nothing the run uses stays in a checkout.
cp "$root/scripts/verify-install.py" "$work/"
verify=(env -u RETROPRISM_DATA_DIR "$python" "$work/verify-install.py")

if [ "$1" = "--fresh-clone" ]; then
  clone="$work/clone"
  git clone -q --no-local "$root" "$clone"
  echo "check-install: fresh clone of $(git -C "$clone" rev-parse --short HEAD)"
  # MaterialX from npm, as scripts/setup-debian.sh installs it: the checkout's copy when present.
  tools="$root/materialx/tools/node_modules/@needle-tools"
  if [ -d "$tools" ]; then
    cp -rL "$root/materialx/tools/node_modules" "$clone/materialx/tools/"
  else
    (cd "$clone/materialx/tools" && npm ci --no-audit --no-fund --loglevel=error)
  fi
  start=$SECONDS
  cmake -S "$clone" -B "$clone/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DRETROPRISM_TESTS=OFF -DRETROPRISM_PYTHON_EXECUTABLE="$python" >"$work/configure.log"
  ninja -C "$clone/build" >"$work/build.log" || { tail -50 "$work/build.log"; exit 1; }
  cmake --install "$clone/build" --prefix "$work/prefix" >/dev/null
  echo "check-install: configured, built and installed in $((SECONDS - start)) s"
  rm -rf "$clone"
  cd "$work"
  "${verify[@]}" "$work/prefix" --source-path "$clone" --materialx
else
  build="$(cd "$1" && pwd)"
  cmake --install "$build" --prefix "$work/installed" >/dev/null
  mv "$work/installed" "$work/moved"
  cd "$work"
  "${verify[@]}" "$work/moved" --source-path "$root" --materialx
fi
echo "check-install: the installed tree works alone"
