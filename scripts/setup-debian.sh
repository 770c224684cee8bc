#!/usr/bin/env bash
# Installs every Debian 12 package retroprism needs to build, test and run.
# Idempotent: packages already present are skipped, and apt is not touched at all
# when nothing is missing. Run as root (or with sudo available).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libopenimageio-dev openimageio-tools libopenexr-dev libimath-dev
  nlohmann-json3-dev libpugixml-dev catch2 libglm-dev libopencolorio-dev
  clang-format universal-ctags libbenchmark-dev fonts-dejavu-core
  libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri glslang-tools spirv-tools
  clang libclang-rt-14-dev llvm
  pybind11-dev python3-dev python3-numpy python3-pytest python3-jsonschema libfftw3-dev
  chromium
  doxygen python3-sphinx python3-breathe python3-myst-parser furo
)

# Node.js runs the MaterialX tool of the tests (any Node.js >= 18: Debian's or one present).
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#packages[@]} Debian packages present"
else
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# MaterialX 1.39.4 (its WebAssembly build, from npm) for the MaterialX tests, at the version
# materialx/tools/package-lock.json pins.
tools="$root/materialx/tools"
if [ ! -f "$tools/node_modules/@needle-tools/materialx/bin/JsMaterialXGenShader.wasm" ]; then
  echo "setup: npm ci in materialx/tools"
  (cd "$tools" && npm ci --no-audit --no-fund --loglevel=error)
fi

# playwright-core (pinned by tests/web/package-lock.json; it downloads no browser) drives
# Debian's chromium over the look-dev page in the browser test (ctest entry web).
web_tests="$root/tests/web"
if [ ! -f "$web_tests/node_modules/playwright-core/package.json" ]; then
  echo "setup: npm ci in tests/web"
  (cd "$web_tests" && npm ci --no-audit --no-fund --loglevel=error)
fi
