#!/usr/bin/env bash
# Runs the pytest-lsp suite against the snell binary.
#   run_pytest.sh VENV SNELL_EXE TEST_DIR
# A missing venv is a failure that says what to do, never a silent pass.
set -euo pipefail
venv="$1" exe="$2" dir="$3"
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c 'import pytest_lsp' 2>/dev/null; then
  echo "lsp_pytest: FAILED: no venv with pytest-lsp at $venv" >&2
  echo "lsp_pytest: run 'bash scripts/setup.sh test' (or set SNELL_LSP_VENV) to make it" >&2
  exit 1
fi
venv="$(cd "$venv" && pwd)"
export SNELL_EXE="$(realpath "$exe")"
dir="$(cd "$dir" && pwd)"
cd "$dir"
exec "$venv/bin/python" -m pytest -q -p no:cacheprovider "$dir"
