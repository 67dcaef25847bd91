#!/usr/bin/env bash
# Snell's one set-up script for Debian 12.
#   bash scripts/setup.sh showcase   install what is missing, build, render the showcase
#   bash scripts/setup.sh test       install what is missing, build, run every test (release),
#                                    then the asan-ubsan tests and a 60 s fuzzing run
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
  catch2 libcli11-dev libfmt-dev nlohmann-json3-dev
  libcpp-httplib-dev                       # snell watch's page
)
if [ "$mode" = test ]; then packages+=(clang libclang-rt-dev clang-format); fi   # the fuzz targets (libFuzzer runtime); the format test
if [ "$mode" = test ]; then packages+=(python3 python3-venv); fi   # the LSP tests' venv (pytest-lsp)
if [ "$mode" = test ]; then packages+=(slurm-wlm); fi   # the farm test (ctest -L farm): a one-node Slurm cluster
if [ "$mode" = test ]; then packages+=(chromium); fi   # the watch page test (ctest -L watch) and scripts/screenshots.sh

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
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
    # 0. The LSP tests' client (tests/lsp/pytest): pytest-lsp from PyPI in a venv,
    #    made only when missing. Debian's python3, whatever else is on PATH.
    venv="${SNELL_LSP_VENV:-$here/build/lsp-venv}"
    if ! "$venv/bin/python" -c 'import pytest_lsp' 2>/dev/null; then
      echo "setup: making $venv (pytest-lsp)"
      rm -rf "$venv"
      /usr/bin/python3 -m venv "$venv"
      "$venv/bin/pip" install -q pytest-lsp==1.0.1
    fi
    # The VS Code extension's npm tools (grammar tests, vsce), only when missing.
    # Debian's nodejs + npm unless a node is already there (nodesource's bundles npm).
    if ! command -v npm >/dev/null; then
      DEBIAN_FRONTEND=noninteractive $sudo apt-get update -qq
      DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends nodejs npm
    fi
    bash scripts/package_vscode.sh test
    # 1. Every test on the release build.
    ctest --preset release -j "$jobs"
    # 2. The same code under AddressSanitizer + UBSan (build/asan-ubsan): the
    #    language, compiler, runtime, hard-case and in-memory LSP tests (e2e and conformance need
    #    the CLI's full renders and stay release-only, for time). UBSan aborts on the
    #    first report (-fno-sanitize-recover). The test preset sets the sanitizer
    #    options: leak suppressions (tests/fuzz/lsan.supp), and
    #    new_delete_type_mismatch=0 because OpenImageIO 2.4's own
    #    TextureSystem::destroy frees its implementation through a sized delete of
    #    the 1-byte interface type (inside libOpenImageIO, not fixable here).
    cmake --preset asan-ubsan >/dev/null
    cmake --build --preset asan-ubsan -j "$jobs" \
      --target test_language test_compiler test_runtime test_runtime_images test_hardcases test_lsp
    # (-LE: conformance cases carry layer tags too, and need the CLI.)
    ctest --preset asan-ubsan -j "$jobs" -L '^(language|compiler|runtime|hardcases|lsp)$' \
      -LE '^(conformance|e2e|cli)$' --timeout 600
    # 3. A bounded fuzzing run (clang, libFuzzer): the front end and compiler for 3/4
    #    of the time, the OBJ reader for 1/4.
    bash bench/fuzz.sh "${SNELL_FUZZ_SECONDS:-60}"
    ;;
  *)
    echo "usage: bash scripts/setup.sh [showcase|test|deps]" >&2
    exit 2
    ;;
esac
