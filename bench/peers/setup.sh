#!/bin/sh
# bench/peers/setup.sh — once per machine: what run.py needs to run Mitsuba 3.
#  - Debian's libllvm19 (bookworm update 1:19.1.7-3~deb12u1): Mitsuba's llvm_ad_rgb
#    variant JIT-compiles with it (the image's LLVM 15 aborts on AVX-512);
#    run.py points DRJIT_LIBLLVM_PATH at /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1.
#  - a venv outside the repository (default ~/.cache/snell-peers-venv, or
#    $SNELL_PEERS_VENV) with mitsuba 3.9.1 (pulls drjit 1.5.0; its Bitmap reads
#    and writes the EXRs) and numpy.
# Opt-in: nothing in CI runs this.
set -eu
VENV=${SNELL_PEERS_VENV:-$HOME/.cache/snell-peers-venv}
LLVM=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1

if [ ! -e "$LLVM" ]; then
  SUDO=; [ "$(id -u)" = 0 ] || SUDO=sudo
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y libllvm19
fi

if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
fi
"$VENV/bin/pip" install --quiet mitsuba==3.9.1 numpy

DRJIT_LIBLLVM_PATH=$LLVM "$VENV/bin/python" - <<'PY'
import drjit as dr, mitsuba as mi
mi.set_variant("llvm_ad_rgb")
print("mitsuba", mi.__version__, "drjit", dr.__version__, "llvm_ad_rgb ok")
PY
echo "venv: $VENV (run.py finds it there; or set SNELL_PEERS_VENV)"
