#!/usr/bin/env bash
# The server's per-viewer frame-rate target (issue 17): with --target-fps 1000 (a 1 ms
# budget no frame meets: a forced budget, nothing timed) a viewer's frames step down to a
# smaller render scale, are sent at that size, and the viewer scales them up: its written
# frames stay full size and, for a flat scene (a lit quad filling the view), match the
# full-size CPU render. Without the target every frame is full size. Stepping back up with
# headroom is app_pace's own test (the same controller).
#   server_target_fps.sh SERVER WORK_DIR VIEWER RENDER COMPARE
source "$(dirname "$0")/cli_harness.sh"
server=$bin
viewer=$3
render=$4
compare=$5
size=96x96
still='sim:realtime=1&noise=0&script=still:600'
printf 'v -10 -10 0\nv 10 -10 0\nv 10 10 0\nv -10 10 0\nf 1 2 3\nf 1 3 4\n' > flat.obj
printf '{"format": "raystream-view", "version": 1, "camera": {"eye": [0, 0, 3], "target": [0, 0, 0], "fov_y_deg": 45}, "lights": [{"position": [1, 2, 6]}]}\n' > flat.json
"$render" --scene flat.obj --size $size --backend cpu --passes 2 --out flat-ref.png > render.out 2>&1 ||
  bad "flat reference: $(cat render.out)"
spid=
trap '[ -n "$spid" ] && kill $spid 2>/dev/null' EXIT
# run NAME SERVER_ARGS...: a server and one headless viewer of 12 frames
run() {
  local name=$1
  shift
  rm -f port.json
  "$server" --scene flat.obj --port 0 --port-file port.json --size $size --threads 1 --encoding raw "$@" 2> "$name-server.log" &
  spid=$!
  for _ in $(seq 100); do [ -s port.json ] && break; sleep 0.1; done
  local port
  port=$(sed -n 's/.*"port":[[:space:]]*\([0-9]*\).*/\1/p' port.json)
  rm -rf "out-$name" && mkdir -p "out-$name"
  timeout 120 "$viewer" --scene flat.obj --tracker "$still" --size $size --headless --frames 12 \
    --refine off --out "out-$name" --stats "$name.json" --server 127.0.0.1:"$port" > "$name.out" 2> "$name.err" ||
    bad "$name: viewer exit $? ($(head -c 300 "$name.err"))"
  kill $spid 2>/dev/null
  wait $spid 2>/dev/null
  spid=
}
jnum() { sed -n "s/.*\"$2\":[[:space:]]*\\([0-9.e+-]*\\).*/\\1/p" "$1"; }
run budget --target-fps 1000
min=$(jnum budget.json remote_scale_min)
awk "BEGIN { exit !(${min:-1} < 1) }" && ok "--target-fps 1000: frames sent at scale ${min}" ||
  bad "no smaller frames: remote_scale_min '${min}' ($(cat budget.err))"
grep -q "scale 0\.[0-9]*" budget.out && ok "the viewer's status shows the scale: $(grep -o 'scale [0-9.]*' budget.out | tail -1)" ||
  bad "scale not on the status line: $(tail -1 budget.out)"
last=out-budget/frame_000011.png
"$compare" "$last" flat-ref.png 0 0 35 > budget.ref && ok "the upscaled frame matches the full-size render: $(cat budget.ref)" ||
  bad "upscaled frame: $(cat budget.ref)"
run plain
min=$(jnum plain.json remote_scale_min)
awk "BEGIN { exit !(${min:-0} == 1) }" && ok "no target: every frame full size" || bad "no target: scale ${min}"
finish
