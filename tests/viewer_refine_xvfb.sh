#!/usr/bin/env bash
# Still-pose refinement in the window under Xvfb (issue 17): local egl, where the renderer
# draws into the window and the mean is kept on the GPU (accumulate.glsl). For frame counts
# 1, 4 and 16 of a still, noiseless tracker the screenshot must come closer to
# raystream-render's 16-sample CPU reference (the same R2 offsets averaged in double), and
# be within 35 dB of it at 16; walking after holding still restarts the accumulation.
#   viewer_refine_xvfb.sh VIEWER WORK_DIR XWD_COMPARE RENDER
source "$(dirname "$0")/cli_harness.sh"
viewer=$bin
compare=$3
render=$4
source "$here/xvfb_harness.sh" 140
size=128x128
still='sim:realtime=1&noise=0&script=still:600'
"$render" --scene box --size $size --backend cpu --passes 2 --samples 16 --out ref16.png > render.out 2>&1 &&
  ok "16-sample CPU reference" || bad "reference render: $(cat render.out)"
# shot N TRACKER [ARGS...]: the window after the status line reports frame N, as N.xwd
shot() {
  local n=$1 tracker=$2
  shift 2
  timeout 120 "$viewer" --tracker "$tracker" --view camera --size $size --threads 1 --frames "$n" \
    --linger 8 --target-fps 0 --local --backend egl "$@" > "$n.out" 2> "$n.err" &
  local vpid=$!
  pids+=($vpid)
  for _ in $(seq 900); do grep -q "frame $n pose" "$n.out" && break; sleep 0.1; done
  sleep 0.5
  xwd -root -silent > "$n.xwd"
  kill -TERM "$vpid" 2>/dev/null
  wait "$vpid"
}
shot 1 "$still"
if no_gl 1.err || grep -q "no GLES context on the window" 1.err; then
  skipped "no GLES context on the window: $(head -c 200 1.err)"
  finish
  exit 77
fi
prev=0
trend=""
fine=1
for n in 1 4 16; do
  [ "$n" = 1 ] || shot "$n" "$still"
  grep -q "frame $n pose .* | $n sample(s)" "$n.out" || bad "frame $n: samples not on the status line: $(tail -1 "$n.out") $(cat "$n.err")"
  d=$("$compare" "$n.xwd" ref16.png 0 0 | sed -n 's/.*PSNR \([0-9.]*\) dB.*/\1/p')
  trend="$trend $n:${d:-none}"
  awk "BEGIN { exit !(${d:-0} > $prev) }" || fine=0
  prev=${d:-0}
done
[ $fine = 1 ] && ok "the window comes closer with more frames (frames:dB)$trend" || bad "not converging (frames:dB)$trend"
awk "BEGIN { exit !($prev >= 35) }" && ok "16 frames: within 35 dB of the 16-sample reference ($prev dB)" ||
  bad "16 frames: $prev dB"
# held still 0.4 s, then walked: the walk restarts what the still part accumulated. The run
# lasts 1.5 s of the tracker's clock, not a number of frames: a fast machine drew 30 frames
# inside the still part and never reached the walk.
timeout 120 "$viewer" --tracker 'sim:realtime=1&noise=0&script=still:0.4,walk:0.6' \
  --view camera --size $size --threads 1 --duration 1.5 --target-fps 0 --local --backend egl \
  --stats walk.json > walk.out 2> walk.err || bad "still then walking: $(head -c 300 walk.err)"
restarts=$(sed -n 's/.*"refine_restarts":[[:space:]]*\([0-9]*\).*/\1/p' walk.json)
[ "${restarts:-0}" -ge 1 ] && ok "still then walking: $restarts restart(s) of the accumulation" ||
  bad "walking did not restart: $(grep -o '"refine_[a-z]*":[^,]*' walk.json) $(tail -1 walk.out)"
grep -q "failed" ./*.err && bad "a step failed: $(grep -h failed ./*.err | head -2)" || ok "no failed steps"
finish
