#!/usr/bin/env bash
# The "Editing scenes" page's editor screenshots (docs/editing.md): a real editor
# (Neovim's built-in LSP client, Debian's neovim) talking to `snell lsp`, in an
# xterm on a virtual X display (Xvfb), captured with ImageMagick's `import`.
# VS Code itself is not packaged for Debian and cannot be installed offline here;
# the extension's client speaks the same protocol to the same server.
#   bash scripts/editor_screenshots.sh [SNELL]   (default build/release/cli/snell)
# Writes docs/images/editor_diagnostics.png and docs/images/editor_completion.png.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
snell="$(realpath "${1:-$here/build/release/cli/snell}")"
for tool in nvim Xvfb xterm import; do
  command -v "$tool" > /dev/null || {
    echo "editor_screenshots: needs $tool (apt-get install neovim xvfb xterm imagemagick)" >&2
    exit 2
  }
done
work="$(mktemp -d)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
cat > "$work/scene.scn" << 'SCN'
// A scene with a typo, as the editor shows it.
camera { location <0, 1.5, -6> look_at <0, 1, 0> }
point_light { position <-3, 6, -4> intensity 80 }
plane { normal <0, 1, 0> material diffuse 0.7 }
sphere { center <0, 1, 0> radus 1 material diffuse <0.8, 0.3, 0.2> }
sphere { center <2, 0.5, 0> radius 0.5 }
SCN
display=":$((90 + RANDOM % 100))"
Xvfb "$display" -screen 0 900x380x24 -nolisten tcp > /dev/null 2>&1 &
pids+=($!)
sleep 1
for shot in diagnostics completion; do
  (cd "$work" && SHOT=$shot SNELL="$snell" DISPLAY="$display" xterm -geometry 98x19+0+0 \
    -fa "DejaVu Sans Mono" -fs 11 -bg "#1e1f22" -fg "#e6e6e6" \
    -e nvim -u "$here/scripts/screenshots/nvim_init.lua" scene.scn) &
  pids+=($!)
  sleep 4
  DISPLAY="$display" import -window root "$here/docs/images/editor_$shot.png"
  kill "${pids[-1]}" 2> /dev/null || true
  sleep 0.5
done
echo "editor_screenshots: wrote docs/images/editor_diagnostics.png and editor_completion.png"
