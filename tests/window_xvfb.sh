#!/usr/bin/env bash
# Under Xvfb: raystream-viewer (remote, from raystream-server) shows frames in its window;
# an xwd screenshot of the window equals the frame it last received.
#   window_xvfb.sh VIEWER WORK_DIR SERVER XWD_COMPARE
source "$(dirname "$0")/cli_harness.sh"
viewer=$bin
server=$3
compare=$4
source "$here/xvfb_harness.sh" 90

"$server" --port 0 --port-file port.json --size 64x64 --threads 1 --quality 90 2> server.log &
pids+=($!)
for _ in $(seq 100); do [ -s port.json ] && break; sleep 0.1; done
port=$(sed -n 's/.*"port":[[:space:]]*\([0-9]*\).*/\1/p' port.json)
timeout 60 "$viewer" --server 127.0.0.1:"$port" --size 64x64 --threads 1 --frames 15 \
  --last last.png --linger 5 > viewer.out 2> viewer.err &
vpid=$!
pids+=($vpid)
for _ in $(seq 300); do [ -s last.png ] && break; sleep 0.1; done
[ -s last.png ] && ok "viewer showed 15 frames and wrote the last" || bad "no last frame: $(cat viewer.err)"
sleep 0.3
xwd -root -silent > shot.xwd && ok "screenshot" || bad "xwd failed"
if "$compare" shot.xwd last.png 0 0 > compare.txt; then
  ok "window shows the last received frame: $(cat compare.txt)"
else
  bad "window differs from the last frame: $(cat compare.txt)"
fi
# a black screen would also "differ"; make sure the frame itself is not blank
"$compare" shot.xwd last.png 100 100 > blank.txt
[ $? -eq 1 ] && ok "the frame is not the empty background" || bad "frame looks like the background: $(cat blank.txt)"
# the status line is drawn in the strip under the image (64..82), never over it
"$compare" shot.xwd --lit 0 64 64 18 > strip.txt && ok "status line drawn under the image: $(cat strip.txt)" || bad "no status line text: $(cat strip.txt)"
kill -TERM "$vpid"
wait "$vpid"
rc=$?
[ $rc -eq 0 ] && ok "viewer closes cleanly on SIGTERM" || bad "viewer exit $rc: $(cat viewer.err)"
grep -q "remote | .* fps" viewer.out && ok "status line" || bad "status: $(cat viewer.out)"
finish
