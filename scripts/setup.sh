#!/usr/bin/env bash
# Snell's one set-up script for Debian 12.
#   bash scripts/setup.sh showcase   install what is missing, build, render the showcase
#   bash scripts/setup.sh test       install what is missing, build, run every test
#   bash scripts/setup.sh deps       only install what is missing
# Installs only missing Debian packages (apt-get update once, only when needed).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
mode="${1:-showcase}"

packages=(
  build-essential cmake ninja-build pkg-config
  libembree-dev libtbb-dev
  libopenimageio-dev openimageio-tools     # openimageio-tools: OIIO's CMake config needs its binaries
  libopencolorio-dev opencolorio-tools
  catch2 libcli11-dev libfmt-dev nlohmann-json3-dev libtinyobjloader-dev
)
if [ "$mode" = test ]; then packages+=(clang); fi   # the fuzz target (libFuzzer)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
[ "$mode" = deps ] && exit 0

jobs="$(nproc)"
cmake --preset release >/dev/null
cmake --build --preset release -j "$jobs"

case "$mode" in
  showcase)
    ./build/release/cli/snell render examples/showcase.scn -o showcase.png -o showcase.exr
    echo "setup: rendered showcase.png and showcase.exr"
    ;;
  test)
    ctest --preset release -j "$jobs"
    ;;
  *)
    echo "usage: bash scripts/setup.sh [showcase|test|deps]" >&2
    exit 2
    ;;
esac
