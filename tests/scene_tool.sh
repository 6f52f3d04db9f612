#!/usr/bin/env bash
# Usage: scene_tool.sh SCENE_BINARY WORK_DIR. Prints "N passed, N failed" and exits non-zero
# on any failure.
source "$(dirname "$0")/cli_harness.sh"

# expect_count NAME SCENE TRIANGLES
expect_count() {
  if "$bin" --scene "$2" --info >info.txt 2>err.txt && grep -qx "triangles: $3" info.txt; then
    ok "$1"
  else
    bad "$1: $(head -c 300 err.txt) $(grep triangles info.txt)"
  fi
}

# expect_fail NAME EXIT REGEX ARGS...: that exit code and exactly one matching stderr line.
expect_fail() {
  fails_cleanly "$@" && ok "$1"
}

expect_count box box 153
expect_count cow1 cow1 5837
expect_count cow17 cow17 98701

# Export cow2 and read it back: same counts, camera and lights.
if "$bin" --scene cow2 --out-obj cow2.obj --info >a.txt 2>err.txt &&
   [ -s cow2.obj ] && [ -s cow2.mtl ] && [ -s cow2.json ] &&
   "$bin" --scene cow2.obj --info >b.txt 2>>err.txt &&
   diff <(grep -Ev "^(scene|wrote)" a.txt) <(grep -Ev "^(scene|wrote)" b.txt) >diff.txt; then
  ok "export round trip"
else
  bad "export round trip: $(head -c 300 err.txt) $(head -c 600 diff.txt)"
fi
if ls ./*.tmp* >/dev/null 2>&1; then bad "temporary file left"; else ok "no temporary files"; fi

expect_fail "missing mesh file" 1 "nothere\.obj" --scene nothere.obj --info
expect_fail "missing cow model" 1 "nocow\.obj" --scene cow1 --cow nocow.obj --info
expect_fail "unknown option" 2 "unknown option" --scene box --frobnicate
expect_fail "no output asked" 2 "--out-obj" --scene box
printf 'v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n' >nan.obj
expect_fail "nan vertex" 1 "non-finite" --scene nan.obj --info

expect_fail "cow0 is no scene" 1 "cow0.*neither box, mirrors, animated, cowN" --scene cow0 --info
# rename() over a FIFO or device replaced the node itself (--out-obj /dev/null as root).
mkfifo fifo.obj
expect_fail "export onto a fifo" 1 "fifo\.obj: not a regular file" --scene box --out-obj fifo.obj
if [ -p fifo.obj ] && [ ! -e fifo.mtl ]; then ok "fifo kept, no mtl"; else bad "fifo replaced or mtl left"; fi
# An unwritable view file leaves no OBJ/MTL half set behind.
expect_fail "unwritable view" 1 "nodir/v\.json" --scene box --out-obj half.obj --out-view nodir/v.json
if [ -e half.obj ] || [ -e half.mtl ]; then bad "unwritable view left half.obj/mtl"; else ok "no half set"; fi

finish
