#!/usr/bin/env bash
# Usage: bench_times_cli.sh BENCH_BINARY WORK_DIR. raystream-bench --times (the frame times
# raystream-glbench measured). Prints "N passed, N failed" and exits non-zero on any
# failure; 77 (skipped) when no EGL context can be made here.
source "$(dirname "$0")/cli_harness.sh"

run() { "$bin" --times --backend egl --size 16 --repeats 1 --passes 2 "$@" box >out.txt 2>err.txt; }

if ! run --chain fused; then
  if grep -qi "egl" err.txt; then echo "skipped: $(head -c 200 err.txt)"; exit 77; fi
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
# Compute kernels: named in the line ("fused compute") with their own kernel's time, and in
# the JSON; a chain they cannot run refused in one line.
if run --kernels compute --json t.json && grep -q " fused compute trace rays " out.txt &&
   grep -q " trace compute [0-9]" out.txt &&
   jq -e '.rows[0].kernels == "compute" and (.rows[0].kernel_ms | has("trace compute"))' \
     t.json >/dev/null; then ok "--kernels compute"
else bad "--kernels compute: $(head -c 300 err.txt) $(head -n 1 out.txt)"; fi
if fails_cleanly "compute on the paper chain" 1 "kernels compute runs the fused chain only" \
  --times --backend egl --size 16 --repeats 1 --kernels compute --chain paper box; then
  ok "compute on the paper chain"; fi
# The figures as JSON beside the text, one row per scene, named on stdout.
if run --chain paper --json t.json && grep -q '^wrote t.json$' out.txt; then
  if jq -e '.mode == "times" and (.rows | length) == 1 and .rows[0].scene == "box" and
            .rows[0].backend == "egl" and .rows[0].chain == "paper" and
            .rows[0].fps > 0 and .rows[0].wall_ms.median > 0 and
            (.rows[0].kernel_ms | has("intersect"))' t.json >/dev/null; then ok "--json"
  else bad "--json: $(head -c 400 t.json)"; fi
else bad "--json: $(head -c 300 err.txt)"; fi
# An instance mode asked for is named in the line (a two-level row must not read as flat).
if run --instances flatten && grep -q " trace rays instances flatten nodes " out.txt &&
   run && ! grep -q " instances " out.txt; then ok "instances named"
else bad "instances named: $(head -c 300 err.txt) $(head -n 1 out.txt)"; fi
# --error: the GL tracer agrees with the CPU reference tracer; the classic environment map
# without shadows does not (its error is what the column reports); shadows none is named.
if run --error --json t.json && jq -e '.rows[0].error.psnr_db >= 57 and
                                       .rows[0].error.bad_share <= 0.001' t.json >/dev/null &&
   grep -q "error against the CPU reference tracer" out.txt; then ok "--error, tracer"
else bad "--error, tracer: $(head -c 300 err.txt) $(head -c 400 t.json)"; fi
if run --error --primary raster --reflections envmap --shadows none --json t.json &&
   grep -q " raster none envmap" out.txt &&
   jq -e '.rows[0].shadows == "none" and .rows[0].error.psnr_db < 40 and
          .rows[0].error.bad_share > 0.01' t.json >/dev/null; then ok "--error, classic unshadowed"
else bad "--error, classic unshadowed: $(head -c 300 err.txt) $(cat out.txt) $(head -c 400 t.json)"; fi
if fails_cleanly "--error alone" 2 "--error goes with --times" --error; then ok "--error alone"; fi
# Bad input: one line naming the option and its valid values, exit 2, no usage dump.
if fails_cleanly "unknown chain" 2 "--chain: .*fused\|separate\|paper" \
  --times --chain wavefront box; then ok "unknown chain"; fi
if fails_cleanly "no scene" 2 "--times needs at least one SCENE" --times; then ok "no scene"; fi
if fails_cleanly "unwritable --json" 1 "cannot write /nonexistent/t.json" \
  --times --size 16 --repeats 1 --json /nonexistent/t.json box; then ok "unwritable --json"; fi
finish
