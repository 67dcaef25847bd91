#!/usr/bin/env bash
# Fails when a tracked C++ file differs from what clang-format makes of it under
# the repository's .clang-format, and names the files. Usage: format_check.sh SRC CLANG_FORMAT
set -euo pipefail
src=$1 cf=$2
cd "$src"
bad=0
while IFS= read -r f; do
  if ! "$cf" --style=file "$f" | cmp -s - "$f"; then
    echo "not formatted: $f (run: clang-format -i $f)"
    bad=1
  fi
done < <(find language compiler runtime cli lsp bench tests -name '*.cpp' -o -name '*.hpp' | sort)
exit $bad
