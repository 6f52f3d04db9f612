#!/usr/bin/env bash
# End to end: raystream-server + headless raystream-viewer + sim: tracker, loopback only.
#   stream_e2e.sh SERVER WORK_DIR VIEWER
source "$(dirname "$0")/cli_harness.sh"
server=$bin
viewer=$3
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; wait 2>/dev/null; }
trap cleanup EXIT
trap "" PIPE # a bad client writes into a connection the server already closed

# jget FILE KEY: a number from a cJSON-printed file
jget() { sed -n "s/^[[:space:]]*\"$2\":[[:space:]]*\([-0-9.e+]*\),\{0,1\}$/\1/p" "$1" | head -n1; }
# check NAME EXPR: awk-evaluated condition over numbers
check() { if awk "BEGIN { exit !($2) }"; then ok "$1"; else bad "$1 ($2)"; fi; }

start_server() { # LOG ARGS...: start on a free port, set $port
  local log=$1
  shift
  rm -f port.json
  "$server" --port 0 --port-file port.json --threads 1 "$@" 2>"$log" &
  pids+=($!)
  server_pid=$!
  for _ in $(seq 100); do [ -s port.json ] && break; sleep 0.1; done
  port=$(jget port.json port)
  [ -n "$port" ] && ok "server $log listening on $port" || bad "server $log did not start: $(cat "$log")"
}

# ---- 1. frames match a local render at the same pose --------------------------------
start_server s1.log --size 64x64 --quality 85
mkdir -p out1
timeout 60 "$viewer" --server 127.0.0.1:"$port" --size 64x64 --headless --threads 1 \
  --duration 2 --stats v1.json --out out1 --every 10 --verify-local > v1.out 2> v1.err
rc=$?
[ $rc -eq 0 ] && ok "viewer exits 0" || bad "viewer exit $rc: $(cat v1.err)"
frames=$(jget v1.json frames)
check "frames arrived ($frames)" "$frames >= 10"
# JPEG quality 85, 4:2:0, on a 64x64 box render in the default camera view (the whole box:
# more edges than the old head-coupled close-up, which measured 36-38 dB): measured
# 30.2-30.8 dB, so the bound is 27 dB (a wrong pose, size or colour order gives < 20 dB)
psnr=$(jget v1.json psnr_min_db)
check "every frame matches a local render at its pose: min PSNR $psnr dB >= 27" "$psnr >= 27"
check "every frame was checked" "$(jget v1.json psnr_checked) == $frames"
check "frame ids in order" "$(jget v1.json frame_order_errors) == 0"
check "pose ids round-trip (only ids this viewer sent, never older)" "$(jget v1.json unknown_pose_ids) == 0"
check "last pose id is one that was sent" "$(jget v1.json last_pose_id) >= 1 && $(jget v1.json last_pose_id) <= $(jget v1.json poses_sent)"
lat=$(jget v1.json latency_median_ms)
check "latency reported ($lat ms median, p99 $(jget v1.json latency_p99_ms))" "$lat > 0"
check "fps reported ($(jget v1.json fps))" "$(jget v1.json fps) > 0"
grep -q "fps | latency .* ms median | link .* Mbit/s" v1.out && ok "status line" || bad "status line: $(head -2 v1.out)"
[ -s out1/frame_000000.png ] && ! ls out1 | grep -q tmp && ok "frames written, no temp files" || bad "frame files: $(ls out1)"
kill "$server_pid"; wait "$server_pid"; rc=$?
[ $rc -eq 0 ] && ok "server stops cleanly on SIGTERM" || bad "server exit $rc"
grep -q "viewer said bye" s1.log && ok "viewer's BYE logged" || bad "no bye in: $(cat s1.log)"

# ---- 1b. a server on compute kernels (--kernels compute): the same frames -------------
rm -f port.json
"$server" --port 0 --port-file port.json --threads 1 --size 64x64 --quality 85 --backend egl \
  --kernels compute --stats s1c.json 2>s1c.log &
pids+=($!)
server_pid=$!
for _ in $(seq 100); do [ -s port.json ] && break; kill -0 "$server_pid" 2>/dev/null || break; sleep 0.1; done
port=$(jget port.json port)
if [ -z "$port" ] && grep -qi "egl" s1c.log; then
  skipped "compute kernels: no EGL context here: $(head -c 200 s1c.log)"
elif [ -z "$port" ]; then
  bad "compute server did not start: $(cat s1c.log)"
else
  grep -q "backend egl (compute kernels)" s1c.log && ok "server names its compute kernels" ||
    bad "server log: $(head -c 300 s1c.log)"
  timeout 60 "$viewer" --server 127.0.0.1:"$port" --size 64x64 --headless --threads 1 \
    --duration 2 --stats v1c.json --verify-local > v1c.out 2> v1c.err ||
    bad "viewer of the compute server: $(cat v1c.err)"
  frames=$(jget v1c.json frames)
  check "compute server: frames arrived (${frames:-0})" "${frames:-0} >= 10"
  psnr=$(jget v1c.json psnr_min_db)
  check "compute server: every frame matches a local render: min PSNR ${psnr:-0} dB >= 27" "${psnr:-0} >= 27"
  check "compute server: every frame was checked" "$(jget v1c.json psnr_checked) == ${frames:-0}"
  kill "$server_pid"; wait "$server_pid"
  grep -q '"kernels":[[:space:]]*"compute"' s1c.json && ok "compute server's stats name the kernels" ||
    bad "compute server stats: $(head -c 300 s1c.json)"
fi

# ---- 2. bad clients while 8 good viewers keep receiving -----------------------------
start_server s2.log --size 96x96 --encoding raw --read-timeout-ms 1000 --stale-ms 100 --max-viewers 32 \
  --render-threads 2
for k in 1 2 3 4 5 6 7 8; do
  timeout 60 "$viewer" --server 127.0.0.1:"$port" --size 96x96 --headless --threads 1 \
    --duration 7 --stats g$k.json --pose-id-base $((k * 1000000)) > g$k.out 2> g$k.err &
  pids+=($!)
  good+=($!)
done
HELLO='\x52\x53\x01\x01\x08\x00\x00\x00\x60\x00\x60\x00\x00\x00\x00\x00'
HELLO_BADTOKEN='\x52\x53\x01\x01\x0c\x00\x00\x00\x60\x00\x60\x00\x00\x04\x00\x00nope'
HELLO_BADSIZE='\x52\x53\x01\x01\x08\x00\x00\x00\x40\x00\x40\x00\x00\x00\x00\x00'
# POSE 7: eye (0.5, 1, 4), target (0.5, 0.5, 0), up (0, 1, 0), fov 45; POSE 8: eye x NaN
POSE='\x52\x53\x01\x03\x70\x00\x00\x00\x07\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\xe0\x3f\x00\x00\x00\x00\x00\x00\xf0\x3f\x00\x00\x00\x00\x00\x00\x10\x40\x00\x00\x00\x00\x00\x00\xe0\x3f\x00\x00\x00\x00\x00\x00\xe0\x3f\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\xf0\x3f\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x46\x40\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00'
POSE_NAN='\x52\x53\x01\x03\x70\x00\x00\x00\x08\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\xf8\x7f\x00\x00\x00\x00\x00\x00\xf0\x3f\x00\x00\x00\x00\x00\x00\x10\x40\x00\x00\x00\x00\x00\x00\xe0\x3f\x00\x00\x00\x00\x00\x00\xe0\x3f\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\xf0\x3f\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x46\x40\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00'
# a viewer that never reads, beside the good ones: once its socket buffers are full its
# frames wait, go stale and are dropped, and nobody else notices
(
  exec 6<>/dev/tcp/127.0.0.1/"$port"
  printf "$HELLO" >&6
  for i in $(seq 140); do printf "$POSE" >&6; sleep 0.05; done
  sleep 0.5
) &
slow=$!
sleep 1
client() { exec 5<>/dev/tcp/127.0.0.1/"$port"; }
done_client() { exec 5>&- 5<&-; }
client; printf 'GET / HTTP/1.0\r\n\r\n' >&5; sleep 0.2; done_client
client; printf "$HELLO" | head -c 10 >&5; done_client
client; printf '\x52\x53\x01\x03\xff\xff\xff\xff' >&5; sleep 0.2; done_client
client; printf "$HELLO_BADTOKEN" >&5; sleep 0.2; done_client
client; printf "$HELLO_BADSIZE" >&5; sleep 0.2; done_client
client; printf "$HELLO$POSE_NAN" >&5; sleep 0.2; done_client
client; printf "$HELLO$POSE$POSE" >&5; done_client # abrupt: gone before its frame
client; sleep 1.5; done_client                     # never says HELLO
# slow drip: a HELLO, then a POSE one byte every 0.15 s (the whole would take 17 s)
client; printf "$HELLO" >&5
for i in $(seq 12); do printf "$POSE" | tail -c +$i | head -c 1 >&5 2>/dev/null; sleep 0.15; done; done_client
for p in "${good[@]}" "$slow"; do wait "$p"; done
kill -0 "$server_pid" 2>/dev/null && ok "server survived every bad client" || bad "server died: $(tail -5 s2.log)"
for k in 1 2 3 4 5 6 7 8; do
  f=$(jget g$k.json frames)
  if [ -n "$f" ] && awk "BEGIN { exit !($f >= 5 && $(jget g$k.json frame_order_errors) == 0 && $(jget g$k.json unknown_pose_ids) == 0) }"; then
    ok "good viewer $k: $f frames, in order, only its own poses"
  else
    bad "good viewer $k: $(cat g$k.json g$k.err 2>&1 | tr '\n' ' ')"
  fi
done
expect() { grep -Eq "$2" s2.log && ok "logged: $1" || bad "not logged: $1 /$2/"; }
expect "garbage" "disconnected: protocol error: [0-9]+ bytes that are no message"
expect "truncated" "disconnected: connection closed mid-message \(10 bytes pending\)"
expect "oversized" "disconnected: protocol error: stream: oversized message"
expect "wrong token" "disconnected: wrong token"
expect "wrong size" "disconnected: this server renders scene box at 96x96, not \(any\) at 64x64"
expect "NaN pose" "disconnected: protocol error: POSE 8: non-finite"
expect "abrupt close" "disconnected: (connection closed without BYE|receive failed|connection lost)"
expect "no hello" "disconnected: timeout: no HELLO within 1.0 s"
expect "slow drip" "disconnected: timeout: message incomplete after 1.0 s .*slow drip"
expect "slow reader's stale frames dropped" "dropped [1-9][0-9]*, poses [0-9]+\]"
n=$(grep -c "disconnected:" s2.log)
check "every disconnect logged with a reason ($n >= 18)" "$n >= 18"
kill "$server_pid"; wait "$server_pid"
grep -q "ERROR: AddressSanitizer\|runtime error" s2.log s1.log && bad "sanitizer report" || ok "no sanitizer reports"

# ---- 3. link emulation: 2 Mbit/s and 50 ms hold a raw 96x96 stream (36 KB a frame) ----
start_server s3.log --size 96x96 --encoding raw --link-mbps 2 --link-latency-ms 50
timeout 60 "$viewer" --server 127.0.0.1:"$port" --size 96x96 --headless --threads 1 \
  --duration 3 --stats l.json > l.out 2> l.err
mbps=$(jget l.json link_mbps)
check "link rate held to 2 Mbit/s (viewer measured $mbps)" "$mbps <= 2.1 && $mbps > 0"
check "frames limited by the link ($(jget l.json fps) fps <= 7)" "$(jget l.json fps) <= 7"
check "latency includes the 50 ms delay ($(jget l.json latency_median_ms) ms)" "$(jget l.json latency_median_ms) >= 50"
kill "$server_pid"; wait "$server_pid"

# ---- 4. bad command lines: one line, non-zero exit ----------------------------------
bin=$server
fails_cleanly "server bad size" 2 "--size: '0x5' is not WxH" --size 0x5
fails_cleanly "server unknown option" 2 "unknown option '--bogus'" --bogus
fails_cleanly "server bad bind" 1 "is not an IPv4 address" --bind nowhere --port 0
bin=$viewer
fails_cleanly "viewer bad server" 1 "is not HOST:PORT" --server nohost --headless --duration 1
fails_cleanly "viewer closed port" 1 "cannot connect" --server 127.0.0.1:1 --headless --duration 1
fails_cleanly "viewer bad tracker" 1 "." --tracker bogus: --headless --duration 1
finish
