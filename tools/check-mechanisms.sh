#!/usr/bin/env bash
# Fail when a tracked source outside lib/core writes again a mechanism the core holds once:
# the monotonic clock (rs_now_ms, rs_status.h), pi (RS_PI, rs_status.h) or the
# little-endian byte codec (private/rs_le.h). Copies drift; call the one in the core.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
mapfile -t files < <(git ls-files 'lib/*' 'backends/*' 'tools/*' 'apps/*' |
  grep -E '\.(c|h|cpp|hpp|glsl)$' | grep -v '^lib/core/')
found=0
check() { # WHAT REGEX
  local hits
  hits=$(grep -nE -- "$2" "${files[@]}" | grep -v 'lib/include/raystream/rs_status.h' || true)
  if [ -n "$hits" ]; then
    echo "check-mechanisms: $1 written again (use the core's):" >&2
    echo "$hits" >&2
    found=1
  fi
}
check "a monotonic clock (rs_now_ms)" 'clock_gettime\(CLOCK_MONOTONIC'
check "pi (RS_PI)" '3\.14159|6\.28318|\bM_PI\b|#define [A-Z_]*PI\b'
check "a little-endian codec (private/rs_le.h)" '\(uint8_t\)\(v >> \(?8|\| *\(?\(uint32_t\)p\[1\] << 8'
[ "$found" -eq 0 ] || exit 1
echo "check-mechanisms: ${#files[@]} files use the core's clock, pi and byte codec"
