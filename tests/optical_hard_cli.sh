#!/usr/bin/env bash
# The optical tracker's hard cases as a user runs them (registered by optical_hard_cli.cmake):
# raystream-optsynth --hard NAME writes each sequence, raystream-track tracks it from the
# files, and every pose reported good (RS_POSE_OK / RS_POSE_RELABELED) is compared with the
# truth: none is beyond its integrity bound (bound=), none but the marker-like stray's
# (--hard stray, which one frame pair cannot refuse) more than 5x its stated error (stated=,
# the expected error) off (the worst ratios are printed), and every frame not solved says
# why (an optical verdict other than SOLVED, or the solver's why=).
# optical_hard_cli.sh OPTSYNTH TRACK WORKDIR
set -euo pipefail
synth=$1
track=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
fail() { echo "optical_hard_cli: $*" >&2; exit 1; }

# check NAME RATE: track DIR at RATE Hz (5 Hz: frames 0.2 s apart, no temporal prior) and
# print "frames good worst worst_bound unexplained" (worst: error / stated, worst_bound:
# error / bound); the truth is matched by frame (seq=).
check() {
  local dir=$work/$1 rate=$2 extra=""
  [ -e "$dir/layout.json" ] && extra="&layout=$dir/layout.json"
  # sigma_px: the centroid noise of the 320x240 spots (radius ~1.6 px) at 2 grey levels
  # (worst clean pose at ~2x the law with 0.04; 0.015 px measured at 640x480).
  "$track" --sigma 0.3 --stats 0 \
    "video:$dir/left_%04d.png,$dir/right_%04d.png?calib=$dir/rig.yaml&rate=$rate&sigma_px=0.04$extra" \
    > "$dir/track-$rate.txt"
  awk '
    FNR == NR { if ($1 !~ /^#/) { x[$1] = $3; y[$1] = $4; z[$1] = $5;
                qx[$1] = $6; qy[$1] = $7; qz[$1] = $8; qw[$1] = $9 } next }
    !/ seq=/ { next }
    { n++
      match($0, / seq=[0-9]+/); f = substr($0, RSTART + 5, RLENGTH - 5) + 0
      match($0, /pos=\[[^]]*\]/); split(substr($0, RSTART + 5, RLENGTH - 6), p, " ")
      match($0, /quat=\[[^]]*\]/); split(substr($0, RSTART + 6, RLENGTH - 7), q, " ")
      match($0, / stated=[0-9.]+deg\/[0-9.]+mm/)
      split(substr($0, RSTART + 8, RLENGTH - 10), s, "deg/")
      good = $0 ~ / RS_POSE_(OK|RELABELED) /
      if (!good) {
        if ($0 ~ / optical=RS_OPTICAL_SOLVED/ && $0 !~ / why="/) unexplained++
        next
      }
      if ($0 !~ / optical=RS_OPTICAL_SOLVED/ || !(f in x)) { unexplained++; next }
      dot = q[1] * qx[f] + q[2] * qy[f] + q[3] * qz[f] + q[4] * qw[f]
      if (dot < 0) dot = -dot
      if (dot > 1) dot = 1
      ang = 2 * atan2(sqrt(1 - dot * dot), dot) * 180 / 3.141592653589793
      d = sqrt((p[1] - x[f])^2 + (p[2] - y[f])^2 + (p[3] - z[f])^2) * 1e3
      r = ang / s[1]; if (d / s[2] > r) r = d / s[2]
      if (!(s[1] > 0 && s[2] > 0)) r = 1e9
      if (r > worst) worst = r
      match($0, / bound=[0-9.]+deg\/[0-9.]+mm/)
      split(substr($0, RSTART + 7, RLENGTH - 9), l, "deg/")
      r = ang / l[1]; if (d / l[2] > r) r = d / l[2]
      if (!(l[1] > 0 && l[2] > 0)) r = 1e9
      if (r > worst_bound) worst_bound = r
      ngood++ }
    END { printf "%d %d %.2f %.2f %d\n", n, ngood, worst, worst_bound, unexplained + 0 }
  ' "$dir/truth.txt" "$dir/track-$rate.txt"
}

# stray-verifier: the stray sequence with the layout's verifier light drawn (--verifier),
# tracked with its layout.json: the stray is refused where it moves the pose, so its
# error against the stated one is asserted too (docs/optical.md, "The verifier").
for name in edges corners stray ghosts stray-verifier; do
  # CI's small size: 320x240 (f = 400 px), the default 2 grey levels of noise; --seed
  # picks other poses for the stray and ghosts runs.
  extra=()
  [ "$name" = stray-verifier ] && extra=(--verifier)
  "$synth" --hard "${name%-verifier}" "${extra[@]}" --size 320x240 \
    --seed "${OPTICAL_HARD_SEED:-1}" "$work/$name" > /dev/null || fail "--hard $name"
  frames=$(grep -vc '^#' "$work/$name/truth.txt")
  for rate in 60 5; do
    read -r n good worst worst_bound unexplained <<<"$(check "$name" "$rate")"
    label=$([ "$rate" = 60 ] && echo tracked || echo cold)
    # The marker-like stray: no test of one frame pair can refuse it (docs/optical.md),
    # so its error against the stated one is printed, not asserted; the bound holds.
    asserted=$([ "$name" = stray ] && echo "printed, not asserted" || echo "asserted <= 5")
    echo "# hard $name, $label: $n frames, $good good, worst error/stated $worst" \
         "($asserted), error/bound $worst_bound, $unexplained unsolved without a reason"
    [ "$n" -eq "$frames" ] || fail "$name: tracked $n of $frames frames"
    [ "$unexplained" -eq 0 ] || fail "$name $label: $unexplained frames not solved and no reason"
    awk -v w="$worst_bound" 'BEGIN { exit !(w <= 1) }' \
      || fail "$name $label: a good pose $worst_bound x its integrity bound off"
    [ "$name" = stray ] && stray_worst=$worst
    [ "$name" = stray ] || awk -v w="$worst" 'BEGIN { exit !(w <= 5) }' \
      || fail "$name $label: a good pose $worst x its stated error off"
    if [ "$name" = stray-verifier ]; then
      refused=$(grep -c ' optical=RS_OPTICAL_VERIFIER' "$work/$name/track-$rate.txt" || true)
      echo "#   verifier: $refused frames refused by it"
      # where three markers alone let a pose beyond 5x through, the verifier refused some
      awk -v w="$stray_worst" 'BEGIN { exit !(w > 5) }' && { [ "$refused" -gt 0 ] ||
        fail "$name $label: the verifier refused nothing"; }
      grep -q ' RS_POSE_OK .* verifier=2' "$work/$name/track-$rate.txt" \
        || fail "$name $label: no good pose with the verifier seen in both views"
    fi
    # Each sequence has frames the tracker solves (a check that cannot pass vacuously).
    [ "$rate" = 5 ] || [ "$good" -gt 0 ] || fail "$name $label: nothing solved"
    # Tracked runs have poses with a prior; cold ones none (frames 0.2 s apart).
    tracked=$(grep -c ' prior=[1-9]' "$work/$name/track-$rate.txt" || true)
    if [ "$rate" = 60 ]; then
      [ "$tracked" -gt 0 ] || fail "$name tracked: no pose with a prior"
    else
      [ "$tracked" -eq 0 ] || fail "$name cold: $tracked poses with a prior"
    fi
  done
done

# A hard sequence has its own length and disturbances; an unknown name is refused.
check_error() {
  set +e
  "$@" > /dev/null 2> "$work/err.txt"
  local rc=$?
  set -e
  [ "$rc" -eq 2 ] || fail "'$*' exited $rc, want 2"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "'$*' did not print exactly one error line"
}
check_error "$synth" --hard walls "$work/x"
grep -q "'walls' is not edges, corners, stray or ghosts" "$work/err.txt" || fail "unknown name"
check_error "$synth" --hard edges --stray "$work/x"
check_error "$synth" --hard edges -n 5 "$work/x"
check_error "$synth" --hard edges --bench
[ ! -e "$work/x" ] || fail "a refused --hard left $work/x behind"
"$synth" --help | grep -q -- '--hard NAME' || fail "--help does not name --hard"
echo "optical_hard_cli: all checks passed"
