#!/usr/bin/env bash
# The viewer rendering on its own backend without a window (--local --headless): for egl,
# osmesa and cpu, and egl and osmesa with compute kernels (--kernels compute), the last
# frame it wrote must be the scene — within 40 dB of
# raystream-render's CPU reference of the scene's camera (all lights, the default of both;
# four sub-pixel samples, what a still viewer's 4th frame has refined to) — so a black or
# empty frame fails
# (the window's twin is window_local_xvfb.sh; remote headless frames: stream_e2e.sh).
#   viewer_headless_local.sh VIEWER WORK_DIR RENDER COMPARE
source "$(dirname "$0")/cli_harness.sh"
viewer=$bin
render=$3
compare=$4
size=128x128
still='sim:realtime=1&noise=0&script=still:600'
"$render" --scene box --size $size --backend cpu --passes 2 --samples 4 --out ref.png > render.out 2>&1 &&
  ok "CPU reference of the scene's camera" || bad "reference render: $(cat render.out)"
for b in egl osmesa cpu egl-compute osmesa-compute; do
  rm -f "headless-$b.png"
  backend=(--backend "${b%-compute}")
  [ "$b" = "${b%-compute}" ] || backend+=(--kernels compute)
  if timeout 120 "$viewer" --tracker "$still" --view camera --size $size --threads 1 --headless \
    --frames 4 --last "headless-$b.png" --local "${backend[@]}" --stats "headless-$b.json" \
    > "headless-$b.out" 2> "headless-$b.err"; then
    "$compare" "headless-$b.png" ref.png 0 0 40 > "headless-$b.ref" &&
      ok "headless $b: the frame is the scene: $(cat "headless-$b.ref")" ||
      bad "headless $b: the frame is not the scene: $(cat "headless-$b.ref")"
    # the stats name what rendered: compute kernels ran as dispatches ("trace compute"),
    # and their frame is the fragment passes' byte for byte
    if [ "$b" != "${b%-compute}" ]; then
      grep -q '"kernel_stage":[[:space:]]*"compute"' "headless-$b.json" &&
        grep -q '"name":[[:space:]]*"trace compute"' "headless-$b.json" &&
        ok "headless $b: the stats show the compute kernels ran" ||
        bad "headless $b: compute kernels not in the stats: $(head -c 600 "headless-$b.json")"
      cmp -s "headless-$b.png" "headless-${b%-compute}.png" &&
        ok "headless $b: the same bytes as fragment passes" ||
        bad "headless $b: differs from the fragment passes' frame"
    else
      grep -q "\"backend\":[[:space:]]*\"$b\"" "headless-$b.json" &&
        ok "headless $b: the stats name the backend" ||
        bad "headless $b: backend not in the stats: $(head -c 600 "headless-$b.json")"
    fi
  elif no_gl "headless-$b.err"; then
    skipped "headless $b: $(head -c 200 "headless-$b.err")"
  else
    bad "headless $b: exit $? ($(head -c 300 "headless-$b.err"))"
  fi
done
# the comparison itself tells another image from the scene (here a lit quad)
printf 'v -10 -10 0\nv 10 -10 0\nv 10 10 0\nv -10 10 0\nf 1 2 3\nf 1 3 4\n' > flat.obj
"$render" --scene flat.obj --size $size --backend cpu --passes 1 --out other.png > other.out 2>&1 ||
  bad "other render: $(cat other.out)"
if "$compare" other.png ref.png 0 0 40 > other.ref; then bad "compare: another image passed as the scene"
else ok "compare: another image is not the scene: $(cat other.ref)"; fi
finish
