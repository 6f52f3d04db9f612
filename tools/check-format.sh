#!/usr/bin/env bash
# Fail when a tracked C or C++ source differs from the committed .clang-format.
# Usage: tools/check-format.sh [--fix]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
fmt=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$fmt" ]; then
  echo "check-format: clang-format-14 not found (tools/deps.sh installs it)" >&2
  exit 1
fi
mapfile -t files < <(git ls-files '*.c' '*.h' '*.cpp' '*.hpp')
if [ "${1:-}" = "--fix" ]; then
  "$fmt" -i "${files[@]}"
  exit 0
fi
if ! "$fmt" --dry-run -Werror "${files[@]}" 2>/dev/null; then
  bad=$("$fmt" --dry-run "${files[@]}" 2>&1 | grep -o '^[^:]*:[0-9]*:[0-9]*: warning' | cut -d: -f1 | sort -u)
  echo "check-format: these files differ from .clang-format (run tools/check-format.sh --fix):" >&2
  echo "$bad" >&2
  exit 1
fi
echo "check-format: ${#files[@]} files clean"
