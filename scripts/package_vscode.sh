#!/usr/bin/env bash
# Builds the VS Code extension editors/vscode/snell-scn.vsix, and runs its
# grammar tests first.
#   bash scripts/package_vscode.sh          regenerate-check the grammar, test, package
#   bash scripts/package_vscode.sh test     only the grammar checks and tests
#   ... --offline                           never install: fail when node_modules is missing
# npm dependencies (vscode-languageclient, @vscode/vsce, vscode-tmgrammar-test, pinned
# in package.json) are installed from the npm registry only when node_modules is
# missing; after that everything runs offline.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ext="$here/editors/vscode"
mode="${1:-package}"

command -v npm >/dev/null || { echo "package_vscode: npm is needed (Debian: nodejs npm)" >&2; exit 1; }
python3 "$here/scripts/gen_vscode_grammar.py" --check
cd "$ext"
if [ ! -x node_modules/.bin/vscode-tmgrammar-test ] || [ ! -d node_modules/vscode-languageclient ]; then
  if [ "${2:-}" = --offline ]; then
    echo "package_vscode: FAILED: no $ext/node_modules; run 'bash scripts/setup.sh test'" >&2
    echo "package_vscode: (or 'bash scripts/package_vscode.sh test' once, with the npm registry)" >&2
    exit 1
  fi
  echo "package_vscode: installing npm dependencies"
  npm install --no-audit --no-fund --loglevel=error
fi
node_modules/.bin/vscode-tmgrammar-test -g syntaxes/snell.tmLanguage.json "tests/*.scn"
[ "$mode" = test ] && exit 0
node_modules/.bin/vsce package --allow-missing-repository --skip-license --out snell-scn.vsix
echo "package_vscode: wrote editors/vscode/snell-scn.vsix"
