#!/usr/bin/env bash
# Fail when a tracked C source includes a raystream header any way but the one spelling:
# public headers as "raystream/rs_x.h" (lib/include and backends/*/include), the core's
# private helpers as "private/rs_x.h". The outside-project consumer test
# (tests/consumer/) includes the installed headers as <raystream/rs_x.h>, as users do.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
mapfile -t files < <(git ls-files '*.c' '*.h' | grep -v '^tests/consumer/')
bad=$(grep -nE '^[[:space:]]*#[[:space:]]*include[[:space:]]*(<|")([^">]*/)?rs_[a-z0-9_]+\.h(>|")' \
  "${files[@]}" | grep -vE '#[[:space:]]*include[[:space:]]*"(raystream|private)/rs_[a-z0-9_]+\.h"' || true)
if [ -n "$bad" ]; then
  echo "check-includes: include raystream headers as \"raystream/rs_x.h\" (or \"private/rs_x.h\"):" >&2
  echo "$bad" >&2
  exit 1
fi
echo "check-includes: ${#files[@]} files use one include spelling"
