#!/usr/bin/env bash
# Under Xvfb, every way the viewer shows a frame in its window (issue 17): local egl (the
# renderer draws straight into the window), local egl through a readback, local osmesa,
# local cpu, local egl and osmesa with compute kernels (--kernels compute), and remote (raw frames from raystream-server on egl, osmesa and cpu, and on
# egl and osmesa with compute kernels) at
# 128x128. A still, noiseless tracker in camera view shows the scene's own camera: an xwd
# screenshot of the window must be within 40 dB of raystream-render's CPU reference of that
# camera and equal the bytes the viewer last rendered or received (--last); a black window
# fails the first, a stale one the second (moving runs of egl and remote check that too).
#   window_local_xvfb.sh VIEWER WORK_DIR SERVER XWD_COMPARE RENDER
source "$(dirname "$0")/cli_harness.sh"
viewer=$bin
server=$3
compare=$4
render=$5
source "$here/xvfb_harness.sh" 120
size=128x128
still='sim:realtime=1&noise=0&script=still:600'
"$render" --scene box --size $size --backend cpu --passes 2 --out ref.png > render.out 2>&1 &&
  ok "CPU reference of the scene's camera" || bad "reference render: $(cat render.out)"

"$server" --port 0 --port-file port.json --size $size --threads 1 --encoding raw 2> server.log &
pids+=($!)
for _ in $(seq 100); do [ -s port.json ] && break; sleep 0.1; done
port=$(sed -n 's/.*"port":[[:space:]]*\([0-9]*\).*/\1/p' port.json)

# show NAME TRACKER ARGS...: run the viewer until its 8th frame is written, screenshot;
# refinement off: these compare single frames (viewer_refine_xvfb tests the average)
show() {
  local name=$1 tracker=$2
  shift 2
  rm -f "$name.png"
  timeout 90 "$viewer" --tracker "$tracker" --view camera --size $size --threads 1 \
    --frames 8 --last "$name.png" --linger 8 --refine off "$@" > "$name.out" 2> "$name.err" &
  local vpid=$!
  pids+=($vpid)
  for _ in $(seq 600); do [ -s "$name.png" ] && break; sleep 0.1; done
  sleep 0.5
  xwd -root -silent > "$name.xwd"
  kill -TERM "$vpid" 2>/dev/null
  wait "$vpid"
  [ -s "$name.png" ] && ok "$name: 8 frames shown" || bad "$name: no frame: $(cat "$name.err")"
}
# the window shows the scene (>= 40 dB of the CPU reference) and the last frame exactly
check_ref() {
  "$compare" "$1.xwd" ref.png 0 0 40 > "$1.ref" && ok "$1: window within 40 dB of the CPU reference: $(cat "$1.ref")" ||
    bad "$1: window is not the scene: $(cat "$1.ref")"
}
check_last() {
  "$compare" "$1.xwd" "$1.png" 0 0 > "$1.last" && ok "$1: window shows the last frame: $(cat "$1.last")" ||
    bad "$1: window is not the last frame: $(cat "$1.last")"
}
for b in egl osmesa cpu; do
  show "local-$b" "$still" --local --backend $b
  check_ref "local-$b"
  check_last "local-$b"
done
show local-egl-readback "$still" --local --backend egl --present readback
check_ref local-egl-readback
# the viewer's own GL backends on compute kernels: egl draws straight into the window
# (the display pass after the dispatches), osmesa's frames are uploaded; the stats must
# show the dispatches ran ("trace compute"), not fragment passes
for b in egl osmesa; do
  show "local-$b-compute" "$still" --local --backend $b --kernels compute --stats "local-$b-compute.json"
  check_ref "local-$b-compute"
  check_last "local-$b-compute"
  grep -q '"name":[[:space:]]*"trace compute"' "local-$b-compute.json" &&
    ok "local-$b-compute: the viewer ran compute kernels" ||
    bad "local-$b-compute: no compute kernels in the stats: $(head -c 600 "local-$b-compute.json")"
done
show remote "$still" --server 127.0.0.1:"$port"
check_ref remote
check_last remote
# the server's other backends (the one above is auto: egl here), and its GL backends on
# compute kernels (--kernels compute): a server that renders black on any would show a
# black window
for b in osmesa cpu egl-compute osmesa-compute; do
  backend=(--backend "${b%-compute}")
  [ "$b" = "${b%-compute}" ] || backend+=(--kernels compute)
  "$server" --port 0 --port-file "port-$b.json" --size $size --threads 1 --encoding raw \
    "${backend[@]}" 2> "server-$b.log" &
  pids+=($!)
  for _ in $(seq 100); do [ -s "port-$b.json" ] && break; sleep 0.1; done
  p=$(sed -n 's/.*"port":[[:space:]]*\([0-9]*\).*/\1/p' "port-$b.json")
  show "remote-$b" "$still" --server 127.0.0.1:"$p"
  check_ref "remote-$b"
  check_last "remote-$b"
  if [ "$b" != "${b%-compute}" ]; then # it ran the compute programs, not fragment passes
    grep -q "backend ${b%-compute} (compute kernels)" "server-$b.log" &&
      ok "remote-$b: the server ran compute kernels" || bad "remote-$b: $(head -c 300 "server-$b.log")"
  fi
done
# moving: a stale window would show an older frame than the last one
show moving-egl 'sim:realtime=1' --local --backend egl
check_last moving-egl
show moving-remote 'sim:realtime=1' --server 127.0.0.1:"$port"
check_last moving-remote
# dynamic resolution: a flat scene (a lit quad filling the view) rendered at half size and
# upscaled by the display step matches the full-size CPU render (egl straight into the
# window, cpu through an upload); files turn scaling off, so these runs wait for frame 8
# on the status line instead of --last
printf 'v -10 -10 0\nv 10 -10 0\nv 10 10 0\nv -10 10 0\nf 1 2 3\nf 1 3 4\n' > flat.obj
printf '{"format": "raystream-view", "version": 1, "camera": {"eye": [0, 0, 3], "target": [0, 0, 0], "fov_y_deg": 45}, "lights": [{"position": [1, 2, 6]}]}\n' > flat.json
"$render" --scene flat.obj --size $size --backend cpu --passes 2 --out flat-ref.png > flat-render.out 2>&1 ||
  bad "flat reference: $(cat flat-render.out)"
scaled() { # NAME ARGS...: until the status line reports frame 8, then a screenshot
  local name=$1
  shift
  timeout 90 "$viewer" --tracker "$still" --size $size --threads 1 --frames 8 --linger 8 \
    --refine off --stats "$name.json" "$@" > "$name.out" 2> "$name.err" &
  local vpid=$!
  pids+=($vpid)
  for _ in $(seq 600); do grep -q "frame 8 pose" "$name.out" && break; sleep 0.1; done
  sleep 0.5
  xwd -root -silent > "$name.xwd"
  kill -TERM "$vpid" 2>/dev/null
  wait "$vpid"
}
for b in egl cpu; do
  scaled "half-$b" --scene flat.obj --local --backend $b --render-scale 0.5
  grep -q "frame 8 pose .* | scale 0.50" "half-$b.out" && ok "half-$b: rendered at scale 0.5" ||
    bad "half-$b: scale not in the status: $(tail -2 "half-$b.out") $(cat "half-$b.err")"
  "$compare" "half-$b.xwd" flat-ref.png 0 0 40 > "half-$b.ref" &&
    ok "half-$b: upscaled flat scene within 40 dB of the full-size render: $(cat "half-$b.ref")" ||
    bad "half-$b: upscaled image: $(cat "half-$b.ref")"
done
# a budget no frame can meet (1 ms) steps the scale down, and the window still shows the
# scene (the scale history is in the stats; stepping back up is app_pace's own test)
scaled budget --local --backend egl --target-fps 1000
steps=$(sed -n 's/.*"scale_steps_down":[[:space:]]*\([0-9]*\).*/\1/p' budget.json)
[ "${steps:-0}" -ge 1 ] && ok "--target-fps 1000: $steps steps down" || bad "no step down: $(cat budget.json budget.err)"
# the bound, measured with all lights (the apps' and the reference's default) at 128x128:
# the correct image upscaled from 0.5 / 0.35 / 0.25 gives 21.0 / 20.3 / 19.1 dB; another
# scene (the lit quad) 11.0 dB, a uniform grey 6.6 dB, a black window 0.7 dB (the box is
# bright with its four lights); 15 dB lies between
"$compare" budget.xwd ref.png 0 0 15 > budget.ref && ok "scaled-down window shows the scene: $(cat budget.ref)" ||
  bad "scaled-down window: $(cat budget.ref)"
# pose prediction to display time: the horizon is the measured latency, capped at 30 ms
pred=$(sed -n 's/.*"predicted_ms_mean":[[:space:]]*\([-0-9.e+]*\).*/\1/p' budget.json)
lat=$(sed -n 's/.*"latency_median_ms":[[:space:]]*\([-0-9.e+]*\).*/\1/p' budget.json)
awk "BEGIN { exit !(${pred:-0} > 0 && ${pred:-0} <= 30.001) }" &&
  ok "poses predicted ${pred} ms ahead (measured latency ${lat} ms median)" || bad "prediction: '${pred}' ms"
grep -q "drawing the frame failed" ./*.err && bad "a draw failed: $(grep -h failed ./*.err | head -2)" || ok "no failed draws"
# the status strip: text under the image, in both lines at 128 px
"$compare" local-cpu.xwd --lit 0 128 128 16 > strip1.txt && "$compare" local-cpu.xwd --lit 0 144 128 16 > strip2.txt &&
  ok "status in two lines under the image" || bad "status strip: $(cat strip1.txt strip2.txt)"
finish
