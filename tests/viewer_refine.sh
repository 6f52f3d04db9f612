#!/usr/bin/env bash
# Still-pose refinement without a window (issue 17): a still, noiseless tracker in camera
# view, --local --headless on cpu, egl and osmesa. Frame k shows the mean of sub-pixel
# samples 0..k, so it must come closer to raystream-render's 16-sample CPU reference of
# the same camera (--samples 16: the same R2 offsets averaged in double) at every doubling
# of the frame count (the trend: single steps of a low-discrepancy sequence's partial means
# are not all closer; at 96x96 frames 7 and 14 measured 0.5 dB below the frame before) and be within 35 dB of it at frame 16; a walking tracker restarts the
# accumulation at every frame (the stats' refine_samples stays 1).
# Remote (raystream-server, raw frames): the viewer holds the resting pose's camera, the
# server averages before encoding; the last frame, of S samples by its header, must be
# within 35 dB of the S-sample reference and closer to it than the first frame.
#   viewer_refine.sh VIEWER WORK_DIR RENDER COMPARE SERVER
source "$(dirname "$0")/cli_harness.sh"
viewer=$bin
render=$3
compare=$4
server=$5
size=96x96
still='sim:realtime=1&noise=0&script=still:600'
"$render" --scene box --size $size --backend cpu --passes 2 --samples 16 --out ref16.png > render.out 2>&1 &&
  ok "16-sample CPU reference" || bad "reference render: $(cat render.out)"
"$render" --scene box --size $size --backend cpu --passes 2 --out ref1.png > render1.out 2>&1 ||
  bad "1-sample render: $(cat render1.out)"
db() { "$compare" "$1" ref16.png 0 0 | sed -n 's/.*PSNR \([0-9.]*\) dB.*/\1/p'; }
one=$(db ref1.png)
echo "one centred sample against 16: $one dB (the edges differ: below the 35 dB bound)"
awk "BEGIN { exit !($one < 35) }" && ok "a single sample is not within 35 dB ($one dB)" ||
  bad "a single sample already passes ($one dB): the bound would not test refinement"
for b in cpu egl osmesa; do
  rm -rf "out-$b"
  mkdir -p "out-$b"
  if timeout 200 "$viewer" --tracker "$still" --view camera --size $size --threads 1 --headless \
    --frames 16 --out "out-$b" --stats "$b.json" --local --backend $b > "$b.out" 2> "$b.err"; then
    trend=""
    prev=0
    fine=1
    for k in 1 2 4 8 16; do
      d=$(db "out-$b/frame_$(printf %06d $((k - 1))).png")
      trend="$trend $k:${d:-none}"
      awk "BEGIN { exit !(${d:-0} > $prev) }" || fine=0
      prev=${d:-0}
    done
    [ $fine = 1 ] && ok "$b: closer at each doubling (frames:dB)$trend" ||
      bad "$b: not converging (frames:dB)$trend"
    awk "BEGIN { exit !($prev >= 35) }" && ok "$b: frame 16 within 35 dB ($prev dB)" ||
      bad "$b: frame 16 at $prev dB"
    grep -q '"refine_samples":[[:space:]]*16' "$b.json" && ok "$b: 16 samples in the stats" ||
      bad "$b: samples: $(grep -o '"refine_samples":[^,]*' "$b.json")"
  elif no_gl "$b.err"; then
    skipped "$b: $(head -c 200 "$b.err")"
  else
    bad "$b: exit $? ($(head -c 300 "$b.err"))"
  fi
done
# motion restarts: held still for 0.4 s, then walked (and again): the accumulation that
# the still part built is restarted by the walk (refine_restarts counts restarts of an
# accumulation of more than one sample). 1.5 s of the tracker's clock, not a frame count,
# so that a fast machine still reaches the walk.
moving='sim:realtime=1&noise=0&script=still:0.4,walk:0.6'
timeout 120 "$viewer" --tracker "$moving" --view camera --size $size --threads 1 --headless \
  --duration 1.5 --stats walk.json --local --backend cpu > walk.out 2> walk.err ||
  bad "still then walking: $(head -c 300 walk.err)"
restarts=$(sed -n 's/.*"refine_restarts":[[:space:]]*\([0-9]*\).*/\1/p' walk.json)
[ "${restarts:-0}" -ge 1 ] && ok "still then walking: $restarts restart(s) of the accumulation" ||
  bad "walking did not restart: $(grep -o '"refine_[a-z]*":[^,]*' walk.json)"
# remote: the server refines while the camera it is sent stays the same
"$server" --port 0 --port-file port.json --size $size --threads 1 --encoding raw 2> server.log &
spid=$!
trap 'kill $spid 2>/dev/null' EXIT
for _ in $(seq 100); do [ -s port.json ] && break; sleep 0.1; done
port=$(sed -n 's/.*"port":[[:space:]]*\([0-9]*\).*/\1/p' port.json)
rm -rf out-remote && mkdir -p out-remote
if timeout 200 "$viewer" --tracker "$still" --view camera --size $size --headless --frames 16 \
  --out out-remote --stats remote.json --server 127.0.0.1:"$port" > remote.out 2> remote.err; then
  n=$(sed -n 's/.*"refine_samples":[[:space:]]*\([0-9]*\).*/\1/p' remote.json)
  "$render" --scene box --size $size --backend cpu --passes 2 --samples "${n:-1}" --out refn.png > rendern.out 2>&1 ||
    bad "reference of ${n} samples: $(cat rendern.out)"
  first=$("$compare" out-remote/frame_000000.png refn.png 0 0 | sed -n 's/.*PSNR \([0-9.]*\) dB.*/\1/p')
  last=$("$compare" out-remote/frame_000015.png refn.png 0 0 | sed -n 's/.*PSNR \([0-9.]*\) dB.*/\1/p')
  awk "BEGIN { exit !(${n:-0} >= 16 && ${last:-0} >= 35 && ${last:-0} > ${first:-99}) }" &&
    ok "remote: the last frame has $n samples, ${last} dB of the $n-sample reference (first frame ${first} dB)" ||
    bad "remote: $n samples, last ${last} dB, first ${first} dB"
else
  bad "remote: exit $? ($(head -c 300 remote.err))"
fi
finish
