#!/usr/bin/env bash
# Usage: bench_cli.sh BENCH_BINARY WORK_DIR. Checks the plumbing of raystream-bench --table 2,
# --builds and --instance-updates (no timing is asserted). Prints "N passed, N failed" and exits non-zero on any
# failure.
source "$(dirname "$0")/cli_harness.sh"

expect_fail() {
  local name=$1 code=$2 regex=$3
  shift 3
  fails_cleanly "$name" "$code" "$regex" "$@" && ok "$name"
}

# --help: usage on stdout with every default, exit 0.
if "$bin" --help >out.txt 2>err.txt && [ ! -s err.txt ] && grep -q -- '--repeats 1..32 .*\[5\]' out.txt &&
    grep -q -- '--backend .*\[auto\]' out.txt && grep -q -- '--times' out.txt; then ok "--help"
else bad "--help: $(head -c 300 err.txt)"; fi
# Bad input: one line naming the option and its valid values (not the usage), exit 2.
expect_fail "unknown table" 2 "--table: '3' is not a whole number in 1\.\.2" --table 3
expect_fail "zero repeats" 2 "--repeats: '0' .*1\.\.32" --repeats 0
expect_fail "zero size" 2 "--size: '0' .*8\.\.16384" --table 2 --size 0
expect_fail "unknown option" 2 "unknown option '--bogus'" --bogus
expect_fail "unknown backend" 2 "--backend: .*vulkan.*auto\|cpu\|egl\|osmesa" --table 2 --backend vulkan
expect_fail "unknown peer" 2 "--peer: 'optix' is not embree\|none" --table 2 --peer optix
expect_fail "unknown builder" 2 "--bvh: .*octree" --table 2 --bvh octree
expect_fail "unknown scene" 2 "unknown scene 'cow3'" --table 2 --scene cow3

for scene in box cow1; do
  if ! "$bin" --table 2 --backend cpu --size 16 --repeats 2 --scene "$scene" >out.txt 2>err.txt; then
    bad "$scene: exit $? ($(head -c 300 err.txt))"
    continue
  fi
  # Every setting the CPU backend renders has its row; the raster ones it refuses are left
  # out of the table and named once under it, not as half the table.
  for setting in "tree BVH, 1 pass" "tree BVH, 2 passes"; do
    if grep -Fq "| $scene" out.txt && grep -F "| $setting |" out.txt | grep -q "$scene"; then
      ok "$scene: row '$setting'"
    else
      bad "$scene: no row '$setting'"
    fi
  done
  if ! grep -q "^| $scene *| raster" out.txt && [ "$(grep -c "raster" out.txt)" -eq 1 ] &&
      grep -q "^Left out on this backend: raster + BVH, 1 pass; raster + BVH, 2 passes (cpu: .*primary rays only" out.txt; then
    ok "$scene: raster left out, named once"
  else bad "$scene: raster rows: $(grep raster out.txt | head -3)"; fi
  # The CPU backend is the reference: its traced images must match it exactly.
  if [ "$(grep "tree BVH" out.txt | grep -c "inf dB, 0.000%, agrees")" -eq 2 ]; then
    ok "$scene: cpu images equal the reference"
  else bad "$scene: cpu image differs from the reference"; fi
  grep -q "^renderer: CPU" out.txt && ok "$scene: renderer string" || bad "$scene: no renderer line"
  grep -q "^load average at start" out.txt && ok "$scene: load average" || bad "$scene: no load average"
  if grep -q "^Peer: Embree" out.txt; then
    for passes in 1 2; do
      row=$(grep -E "^\| $scene +\| $passes \|" out.txt)
      if [ -z "$row" ]; then bad "$scene: no peer row for $passes pass(es)"; continue; fi
      # Same work: the peer's image agrees with the reference, and both replays (one ray at a
      # time, streams) find exactly the hits it found under the reference's paths, on as
      # many rays as the backend traced.
      if echo "$row" | grep -q "agrees"; then ok "$scene/$passes: Embree image agrees"
      else bad "$scene/$passes: Embree image differs: $row"; fi
      if echo "$row" | grep -Eq "\(([0-9]+); \1, \1\)"; then ok "$scene/$passes: replay hits equal"
      else bad "$scene/$passes: replay hits differ: $row"; fi
      sum=$(echo "$row" | awk -F'|' '{split($4, n, " "); print n[1] + n[3]}')
      back=$(echo "$row" | awk -F'|' '{gsub(/ /, "", $10); print $10}')
      # fp32 hits may send a rare path another way: the counts agree within 1%.
      if [ -n "$sum" ] && [ -n "$back" ] && [ $(( (sum - back) * 100 )) -le "$back" ] &&
          [ $(( (back - sum) * 100 )) -le "$back" ]; then
        ok "$scene/$passes: the backend's rays ($back, peer $sum)"
      else bad "$scene/$passes: peer traced $sum rays, the backend $back"; fi
      # the ratio of one alternating run: median (lowest-highest) of the per-round ratios
      ratio=$(echo "$row" | awk -F'|' '{gsub(/^ +| +$/, "", $12); print $12}')
      if [[ "$ratio" =~ ^([0-9.]+)\ \(([0-9.]+)–([0-9.]+)\)$ ]] &&
          awk -v m="${BASH_REMATCH[1]}" -v lo="${BASH_REMATCH[2]}" -v hi="${BASH_REMATCH[3]}" \
            'BEGIN { exit !(m > 0 && lo <= m && m <= hi) }'; then
        ok "$scene/$passes: backend / Embree per round ($ratio)"
      else bad "$scene/$passes: backend / Embree cell: '$ratio'"; fi
    done
    grep -q "^Peer: .*measured alternately: each of 2 round(s) one backend frame" out.txt &&
      ok "$scene: the peer's ratio says it alternates" || bad "$scene: peer header: $(grep '^Peer' out.txt)"
  else
    grep -q "^Peer: not built" out.txt && ok "$scene: peer absence stated" || bad "$scene: no peer line"
  fi
done

# --json: the rows beside the table (refusals as such), named on stdout.
if "$bin" --table 2 --backend cpu --size 16 --repeats 1 --scene box --peer none --json t2.json \
    >out.txt 2>err.txt && grep -q '^wrote t2.json$' out.txt &&
    jq -e '.mode == "table2" and (.rows | length) == 4 and
           ([.rows[] | select(.refused)] | length) == 2 and
           (.rows[0].fps > 0) and .rows[0].paper_fps == 443.34' t2.json >/dev/null; then
  ok "table 2 --json"
else bad "table 2 --json: $(head -c 300 err.txt) $(head -c 300 t2.json)"; fi
if "$bin" --scene box --size 16 --flat-size 8 --repeats 1 --json t1.json >out.txt 2>err.txt &&
    jq -e '.mode == "table1" and .rows[0].scene == "box" and .rows[0].hit_numbers.sah > 0 and
           .rows[0].paper_hit_numbers.none == 174.652' t1.json >/dev/null; then
  ok "table 1 --json"
else bad "table 1 --json: $(head -c 300 err.txt) $(head -c 300 t1.json)"; fi
# Table 2 without --backend renders on the GPU where a GL context opens (auto), and says in
# one line when it falls back to cpu.
if "$bin" --table 2 --size 16 --repeats 1 --scene box --peer none >auto.txt 2>auto_err.txt; then
  if grep -q "^Table 2 on backend egl\|^Table 2 on backend osmesa" auto.txt; then ok "default backend: GL"
  elif grep -q "^Table 2 on backend cpu" auto.txt && [ "$(grep -c 'cpu' auto_err.txt)" -eq 1 ]; then
    ok "default backend: cpu, fallback stated"
  else bad "default backend: $(head -n 1 auto.txt) / $(head -c 200 auto_err.txt)"; fi
else bad "default backend: $(head -c 300 auto_err.txt)"; fi

# A GL backend, when built: the raster settings run (not refused), every image agrees with
# the reference, per-kernel rows come from stats.kernels[], and the renderer is named.
if "$bin" --table 2 --backend egl --size 16 --repeats 1 --scene box --peer none \
    >egl.txt 2>egl_err.txt; then
  for setting in "tree BVH, 1 pass" "raster + BVH, 1 pass" "raster + BVH, 2 passes" \
      "tree BVH, 2 passes"; do
    row=$(grep -F "| $setting |" egl.txt | grep -E "^\| box +\|" | head -1)
    if echo "$row" | grep -q "agrees"; then ok "egl: '$setting' agrees with the reference"
    else bad "egl: '$setting': $row"; fi
  done
  grep -q "Left out" egl.txt && bad "egl refused a setting" || ok "egl: nothing refused"
  grep -Eq "^\| box +\| tree BVH, 1 pass \| [a-z]+ \| [0-9]+ \|" egl.txt &&
    ok "egl: per-kernel rows" || bad "egl: no per-kernel rows"
  grep -q "^renderer: " egl.txt && ! grep -q "^renderer: CPU" egl.txt &&
    ok "egl: renderer string" || bad "egl: renderer string missing"
elif no_gl egl_err.txt; then
  skipped "egl: $(head -c 300 egl_err.txt)"
else
  bad "egl: $(head -c 300 egl_err.txt)"
fi

# --builds: our build beside the peer's, one row per thread count, and the tree built on
# two threads is the one-thread tree.
if "$bin" --builds --scene cow1 --threads 2 >build.txt 2>build_err.txt; then
  for t in 1 2; do
    row=$(grep -E "^\| cow1 +\| +5837 \| $t \|" build.txt)
    if [ -z "$row" ]; then bad "builds: no row for $t thread(s)"
    elif echo "$row" | grep -q "| yes |$"; then ok "builds: $t thread(s), same tree"
    else bad "builds: $t thread(s): $row"; fi
  done
  grep -q "median of 7 builds" build.txt && ok "builds: at least 7 builds" ||
    bad "builds: repeats not raised to 7"
else
  bad "builds: exit $? ($(head -c 300 build_err.txt))"
fi

# --instance-updates: one row per instance count (triangles: 96 a sphere, 2 of floor), the
# renderer's path named (the CPU backend renders two levels and rebuilds its TLAS: tlas), JSON rows.
if "$bin" --instance-updates --backend cpu --size 16 --repeats 2 --json iu.json 3 40 \
    >iu.txt 2>iu_err.txt; then
  for row in "3 290" "40 3842"; do
    if grep -qE "^ +${row% *} +${row#* } .* cpu +tlas " iu.txt; then ok "instance-updates: row $row"
    else bad "instance-updates: no row '$row' in $(cat iu.txt)"; fi
  done
  if jq -e '.mode == "instance-updates" and (.rows | length) == 2 and .rows[1].instances == 40
      and .rows[1].tlas_upload_bytes > .rows[0].tlas_upload_bytes' iu.json >/dev/null; then
    ok "instance-updates: JSON rows"
  else bad "instance-updates: JSON $(head -c 300 iu.json)"; fi
else
  bad "instance-updates: exit $? ($(head -c 300 iu_err.txt))"
fi
expect_fail "instance-updates: a bad count" 2 "not an instance count" --instance-updates \
  --backend cpu 0
expect_fail "instance-updates and --animate" 2 "separate runs" --instance-updates --animate 2 cow1
finish
