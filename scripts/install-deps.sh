#!/usr/bin/env bash
# Installs the Debian 12 packages jnd needs to build, test and benchmark.
# Idempotent and non-interactive: only missing packages are installed.
# Uses sudo when not root.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libstb-dev libopenexr-dev libcjson-dev zlib1g-dev libdeflate-dev  # image I/O, JSON
  fonts-dejavu-core                                # the font embedded in report pictures
  liblapacke-dev                                   # PCA
  libassimp-dev libmeshoptimizer-dev               # asset import, LOD
  libegl-dev libgl-dev libegl1-mesa-dev libgl1-mesa-dri libgbm-dev  # headless GL (llvmpipe)
  clang libclang-rt-14-dev                         # libFuzzer + sanitizers
  jq time                                          # JSON checks in tests; peak memory in make bench
  libjxl-devtools                                  # butteraugli_main, the peer in `make bench`
  assimp-testmodels                                # real (and malformed) glTF files for tests
  libsquish-dev                                    # BC1/BC4/BC5 reference encoder
  munge slurmctld slurmd slurm-client              # jnd batch --slurm, tested on a real one-node Slurm
  chromium                                         # the HTML report's browser test (headless)
  python3-dev python3-cffi python3-numpy python3-pytest  # the Python package (python/) and its tests
  blender                                          # the add-on's headless test (blender/, Blender 3.4)
  xvfb                                             # the add-on's panel screenshot (blender/tests/panel_screenshot.py)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
# npm only where no node toolchain is present (Debian's npm conflicts with other node installs)
if ! command -v npm >/dev/null 2>&1; then missing+=(npm); fi

if [ ${#missing[@]} -ne 0 ]; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  echo "install-deps: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

# The pinned npm package of real controller models that the webxr tests and
# the benchmarks render (bench/webxr_assets.sh): fetched once into a cache
# outside the build folder, so that the tests make no network request.
# Without a network the webxr tests skip (and CI, where a skip fails, fails).
. "$(dirname "$0")/../bench/webxr_assets.sh"
npm_cache_install @webxr-input-profiles/assets "$WEBXR_ASSETS_VERSION" "$WEBXR_ASSETS_SHA256" "$WEBXR_ASSETS_CHECK" \
  "the webxr tests skip"

# The pinned playwright-core that drives Debian's chromium in the report's
# browser test (tests/browser/playwright.sh), the same way.
. "$(dirname "$0")/../tests/browser/playwright.sh"
npm_cache_install playwright-core "$PLAYWRIGHT_CORE_VERSION" "$PLAYWRIGHT_CORE_SHA256" "$PLAYWRIGHT_CORE_CHECK" \
  "the report's browser test skips"

# The pinned Khronos glTF-Validator that checks the models jnd writes
# (tests/e2e/budget.sh), the same way.
. "$(dirname "$0")/gltf_validator.sh"
npm_cache_install gltf-validator "$GLTF_VALIDATOR_VERSION" "$GLTF_VALIDATOR_SHA256" "$GLTF_VALIDATOR_CHECK" \
  "the budget test's validator check skips"
