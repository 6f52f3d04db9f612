#!/usr/bin/env bash
# raystream-optsynth and raystream-track video: end to end (registered by
# optical_cli.cmake): optical_cli.sh OPTSYNTH TRACK WORKDIR
set -euo pipefail
synth=$1
track=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
fail() { echo "optical_cli: $*" >&2; exit 1; }

# Frames of the simulator's motion, then tracked from the files like any other source.
"$synth" -n 6 --stray --seed 3 "$work/seq" > /dev/null
[ "$(grep -vc '^#' "$work/seq/truth.txt")" -eq 6 ] || fail "truth lines"
uri="video:$work/seq/left_%04d.png,$work/seq/right_%04d.png?calib=$work/seq/rig.yaml&rate=60"
out=$("$track" --sigma 1 --stats 0 "$uri")
[ "$(grep -c 'RS_POSE_OK' <<<"$out")" -eq 6 ] || fail "expected 6 solved poses: $out"
grep -q '^# stats samples=6 ' <<<"$out" || fail "stats line"
# The first pose is the truth's (1 mm, 0.01 rad: far above the error at this noise).
read -r x y z <<<"$(grep -v '^#' "$work/seq/truth.txt" | head -n 1 | cut -d' ' -f3-5)"
first=$(grep -m1 ' seq=0 ' <<<"$out" | sed 's/.*pos=\[\([^]]*\)\].*/\1/')
awk -v a="$first" -v x="$x" -v y="$y" -v z="$z" 'BEGIN { split(a, p, " ");
  d = sqrt((p[1]-x)^2 + (p[2]-y)^2 + (p[3]-z)^2); exit !(d < 0.001) }' \
  || fail "first pose $first is not the truth $x $y $z"
# Each optical sample states its own error: the first pose is within 5x of it.
grep -v '^#' <<<"$out" | grep -qv ' optical=RS_OPTICAL_SOLVED' && fail "a sample not solved: $out"
stated=$(grep -m1 ' seq=0 ' <<<"$out" | sed 's/.* stated=[^/]*\/\([0-9.]*\)mm.*/\1/')
awk -v a="$first" -v x="$x" -v y="$y" -v z="$z" -v s="$stated" 'BEGIN { split(a, p, " ");
  d = sqrt((p[1]-x)^2 + (p[2]-y)^2 + (p[3]-z)^2); exit !(s > 0 && d * 1e3 <= 5 * s) }' \
  || fail "first pose $first is more than 5x its stated ${stated} mm from the truth"

check_error() {
  local want=$1; shift
  set +e
  "$@" > /dev/null 2> "$work/err.txt"
  local rc=$?
  set -e
  [ "$rc" -eq "$want" ] || fail "'$*' exited $rc, want $want"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "'$*' did not print exactly one error line"
}
check_error 2 "$synth"
check_error 2 "$synth" --dim 3 "$work/x"
check_error 2 "$synth" --script fly "$work/x"
check_error 2 "$track" "video:$work/seq/left_%04d.png?calib=$work/seq/rig.yaml"
check_error 1 "$track" "video:$work/seq/left_%04d.png,$work/seq/right_%04d.png?calib=$work/none.yaml"
check_error 1 "$track" "video:$work/none_%04d.png,$work/seq/right_%04d.png?calib=$work/seq/rig.yaml"
echo "optical_cli: all checks passed"
