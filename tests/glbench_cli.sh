#!/usr/bin/env bash
# Usage: glbench_cli.sh GLBENCH_BINARY WORK_DIR. Prints "N passed, N failed" and exits
# non-zero on any failure; 77 (skipped) when no EGL context can be made here.
source "$(dirname "$0")/cli_harness.sh"

run() { "$bin" --backend egl --size 16 --frames 1 --passes 2 "$@" box >out.txt 2>err.txt; }

if ! run --chain fused; then
  if no_gl err.txt; then echo "skipped: $(head -c 200 err.txt)"; exit 77; fi
  bad "fused chain: $(head -c 300 err.txt)"
fi
# Each chain is named in the result line with its own kernels' times.
for case in "fused: trace" "separate: intersect shade" \
            "paper: intersect environment shading next ray"; do
  chain=${case%%:*}
  if ! run --chain "$chain"; then bad "$chain: $(head -c 300 err.txt)"; continue; fi
  line=$(head -n 1 out.txt)
  if ! grep -q " $chain trace rays" <<<"$line"; then bad "$chain: not named in '$line'"; continue; fi
  missing=""
  for k in ${case#*:}; do
    [ "$k" = "next" ] && k="next ray"
    [ "$k" = "ray" ] && continue
    grep -q " $k [0-9]" <<<"$line" || missing="$missing $k"
  done
  if [ -n "$missing" ]; then bad "$chain: no time for$missing in '$line'"; else ok "$chain"; fi
done
if fails_cleanly "unknown chain" 2 "usage: raystream-glbench .*--chain fused\|separate\|paper" \
  --chain wavefront box; then ok "unknown chain"; fi
finish
