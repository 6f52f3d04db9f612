#!/usr/bin/env bash
# raystream-calib end to end (registered by calib_cli.cmake): calib_cli.sh TOOL WORKDIR
set -euo pipefail
tool=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
fail() { echo "calib_cli: $*" >&2; exit 1; }

# Synthetic checkerboard pairs of a known rig, calibrated back: the baseline comes out.
"$tool" --synth "$work/cal" --views 12 > "$work/synth.txt"
grep -q 'wrote 12 checkerboard pairs' "$work/synth.txt" || fail "synth"
out=$("$tool" -o "$work/rig.json" "$work/cal/left_%04d.png" "$work/cal/right_%04d.png")
grep -q '12 of 12 pairs used' <<<"$out" || fail "pairs: $out"
grep -q 'baseline 0.4000 m' <<<"$out" || fail "baseline: $out"
[ -s "$work/rig.json" ] || fail "no rig file"

# --help: every option with its default, on stdout, exit 0.
"$tool" --help > "$work/help.txt" || fail "--help exit"
grep -q -- '--board CxR .*\[9x6\]' "$work/help.txt" || fail "--help: no defaults"
# --synth DIR is made with its parents (the one rule for every output folder).
"$tool" --synth "$work/new/deep" --views 2 > /dev/null || fail "--synth into a new folder"
[ -s "$work/new/deep/true.yaml" ] || fail "--synth: no true.yaml in the new folder"

# Bad input: one line on stderr, non-zero exit.
check_error() {
  local want=$1; shift
  set +e
  "$tool" "$@" > /dev/null 2> "$work/err.txt"
  local rc=$?
  set -e
  [ "$rc" -eq "$want" ] || fail "'$*' exited $rc, want $want"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "'$*' did not print exactly one error line"
}
check_error 2
check_error 2 --board 2x9 a b
check_error 2 --frobnicate a b
check_error 2 --max 1 a b
grep -q -- "--max: '1' .*5..10000" "$work/err.txt" || fail "--max 1: range not named"
check_error 1 "$work/none_%04d.png" "$work/cal/right_%04d.png"
check_error 1 -o "$work/rig.txt" "$work/cal/left_%04d.png" "$work/cal/right_%04d.png"
# The wrong board size: found in no view, so too few views.
check_error 1 --max 5 -o "$work/r.yaml" "$work/cal/left_%04d.png" "$work/cal/right_%04d.png" --board 7x6
echo "calib_cli: all checks passed"
