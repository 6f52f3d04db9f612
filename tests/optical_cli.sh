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

# With --verifier: the fourth light drawn and DIR/layout.json written; tracked with it, every
# sample is solved with the verifier found in both views, and the pose is still the truth's.
"$synth" -n 4 --verifier --seed 3 "$work/ver" > /dev/null
[ -s "$work/ver/layout.json" ] || fail "--verifier wrote no layout.json"
uri="video:$work/ver/left_%04d.png,$work/ver/right_%04d.png?calib=$work/ver/rig.yaml&layout=$work/ver/layout.json&rate=60"
out=$("$track" --sigma 1 --stats 0 "$uri")
[ "$(grep -c 'RS_POSE_OK.* optical=RS_OPTICAL_SOLVED verifier=2' <<<"$out")" -eq 4 ] \
  || fail "expected 4 poses with the verifier in both views: $out"
read -r x y z <<<"$(grep -v '^#' "$work/ver/truth.txt" | head -n 1 | cut -d' ' -f3-5)"
first=$(grep -m1 ' seq=0 ' <<<"$out" | sed 's/.*pos=\[\([^]]*\)\].*/\1/')
awk -v a="$first" -v x="$x" -v y="$y" -v z="$z" 'BEGIN { split(a, p, " ");
  d = sqrt((p[1]-x)^2 + (p[2]-y)^2 + (p[3]-z)^2); exit !(d < 0.001) }' \
  || fail "verifier: first pose $first is not the truth $x $y $z"
# Without the layout the same frames see the fourth light as a stray: no verifier= field.
out=$("$track" --sigma 1 --stats 0 "${uri/&layout=$work\/ver\/layout.json/}")
grep -q ' verifier=' <<<"$out" && fail "verifier= printed without a verifier layout"

# flips FILE: how many consecutive quaternions (4 numbers per line on stdin) lie in
# opposite hemispheres (q and -q are one rotation; a flip is a jump in the output).
flips() {
  awk 'NR > 1 { d = $1 * a + $2 * b + $3 * c + $4 * e; if (d < 0) n++ }
       { a = $1; b = $2; c = $3; e = $4 } END { print n + 0 }'
}

# The README's pair of lines as written (default sequence, 640x480): every one of the 120
# frame pairs shows all three markers, so every one is tracked, and the quaternions of
# the track output and of truth.txt are continuous (no sign flips near 180 degrees).
"$synth" "$work/readme" > "$work/readme.out"
grep -q 'video:' "$work/readme.out" || fail "optsynth does not say how to track its frames"
out=$("$track" --sigma 1 --stats 0 \
  "video:$work/readme/left_%04d.png,$work/readme/right_%04d.png?calib=$work/readme/rig.yaml")
[ "$(grep -c 'RS_POSE_OK.* markers=3' <<<"$out")" -eq 120 ] \
  || fail "default sequence: $(grep -c 'RS_POSE_OK' <<<"$out") of 120 frames tracked"
n=$(grep ' seq=' <<<"$out" | sed 's/.*quat=\[\([^]]*\)\].*/\1/' | flips)
[ "$n" -eq 0 ] || fail "track output: $n quaternion sign flips"
# A longer run (three seconds, through turns and the shake) keeps truth.txt continuous.
"$synth" -n 360 --size 64x64 "$work/long" > /dev/null
n=$(grep -v '^#' "$work/long/truth.txt" | cut -d' ' -f6-9 | flips)
[ "$n" -eq 0 ] || fail "truth.txt: $n quaternion sign flips"

# DIR is made with its parents, every file named on stdout; --help lists the defaults.
"$synth" -n 2 --size 64x64 "$work/new/deep" > "$work/new.out" || fail "optsynth into a new folder"
grep -q "^wrote $work/new/deep/rig.yaml$" "$work/new.out" || fail "rig.yaml not named on stdout"
"$synth" --help | grep -q -- '--frames 1..100000 .*\[120\]' || fail "--help: no defaults"

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
grep -q -- "--dim: '3' .*0..2" "$work/err.txt" || fail "--dim 3: range not named"
check_error 2 "$synth" --script fly "$work/x"
[ ! -e "$work/x" ] || fail "a refused --script left $(ls "$work/x") behind"
check_error 2 "$track" "video:$work/seq/left_%04d.png?calib=$work/seq/rig.yaml"
check_error 1 "$track" "video:$work/seq/left_%04d.png,$work/seq/right_%04d.png?calib=$work/none.yaml"
check_error 1 "$track" "video:$work/none_%04d.png,$work/seq/right_%04d.png?calib=$work/seq/rig.yaml"

# Camera masks as images (mask0file=, mask1file=: PGM or PNG of the camera's frame size,
# nonzero pixels masked): an all-zero mask changes nothing, a full one leaves nothing to
# match; a missing file, a file that is no image and one of another size are one-line
# errors naming the option.
pgm() { # pgm FILE W H BYTE
  { printf 'P5\n%d %d\n255\n' "$2" "$3"; head -c $(($2 * $3)) /dev/zero | tr '\0' "$4"; } > "$1"
}
pgm "$work/zero.pgm" 640 480 '\000'
pgm "$work/full.pgm" 640 480 '\377'
pgm "$work/small.pgm" 320 240 '\000'
echo "not an image" > "$work/text.pgm"
base="video:$work/seq/left_%04d.png,$work/seq/right_%04d.png?calib=$work/seq/rig.yaml&rate=60"
out=$("$track" --sigma 1 --stats 0 "$base&mask1file=$work/zero.pgm")
[ "$(grep -c 'RS_POSE_OK' <<<"$out")" -eq 6 ] || fail "zero mask image: $out"
out=$("$track" --sigma 1 --stats 0 "$base&mask0file=$work/full.pgm")
grep -q 'RS_POSE_OK' <<<"$out" && fail "a full mask image left poses: $out"
[ "$(grep -c 'optical=RS_OPTICAL_TOO_FEW_MATCHES' <<<"$out")" -eq 6 ] \
  || fail "full mask image: frames not refused for too few matches: $out"
check_error 1 "$track" "$base&mask1file=$work/none.pgm"
grep -q "mask1file '$work/none.pgm': cannot open" "$work/err.txt" || fail "missing mask file"
check_error 1 "$track" "$base&mask0file=$work/text.pgm"
grep -q "mask0file .* is not an image" "$work/err.txt" || fail "mask file not an image"
check_error 1 "$track" "$base&mask1file=$work/small.pgm"
grep -q "mask1file .* is 320x240, camera 1's frames 640x480" "$work/err.txt" \
  || fail "mask file of the wrong size: $(cat "$work/err.txt")"
echo "optical_cli: all checks passed"
