#!/usr/bin/env bash
# Usage: animate_cli.sh RENDER_BINARY WORK_DIR VIEWER_BINARY. raystream-render --animate COUNT renders
# frames through rs_renderer_update_vertices() (an instanced herd, cowNi, through
# rs_renderer_update_instances()) and names each image FILE-NNNN.png; each must
# equal a single render of that --frame (a fresh set_scene), bit for bit on the CPU backend
# (PNG bytes) and on EGL where a context opens. Static scenes refuse --frame in one line.
source "$(dirname "$0")/cli_harness.sh"

same_frames() { # BACKEND SCENE FIRST COUNT: the run's frames against single renders
  local backend=$1 scene=$2 first=$3 count=$4 f name
  if ! "$bin" --scene "$scene" --backend "$backend" --size 40x40 --frame "$first" \
      --animate "$count" --out run.png --stats run.json >stdout.txt 2>stderr.txt; then
    if [ "$backend" != cpu ] && no_gl stderr.txt; then skipped "$backend: $(cat stderr.txt)"; return; fi
    bad "$backend $scene --animate: $(cat stderr.txt)"; return
  fi
  grep -q '"updates":[[:space:]]*'"$((count - 1))" run.json || { bad "$backend $scene: stats $(cat run.json)"; return; }
  # an instanced herd moves by its instance transforms (rs_renderer_update_instances)
  local inst=0
  case $scene in cow*i) inst=$((count - 1)) ;; esac
  grep -q '"instance_updates":[[:space:]]*'"$inst" run.json || { bad "$backend $scene: instance updates $(cat run.json)"; return; }
  for ((f = first; f < first + count; f++)); do
    name=$(printf 'run-%04d.png' "$f")
    grep -q "$name" stdout.txt || { bad "$backend $scene: $name not named on stdout"; return; }
    "$bin" --scene "$scene" --backend "$backend" --size 40x40 --frame "$f" --out one.png \
      >/dev/null 2>stderr.txt || { bad "$backend $scene --frame $f: $(cat stderr.txt)"; return; }
    cmp -s "$name" one.png || { bad "$backend $scene: frame $f of the run differs from --frame $f"; return; }
  done
  ok "$backend $scene: frames $first..$((first + count - 1)) of a run equal single --frame renders"
}

same_frames cpu animated 35 3
same_frames cpu cow4 0 3
same_frames cpu cow4i 0 3
same_frames cpu cow5i 40 2
same_frames egl animated 36 2
same_frames egl cow3i 10 2

# a moving frame is not the still one
"$bin" --scene animated --backend cpu --size 40x40 --out f0.png >/dev/null 2>&1
"$bin" --scene animated --backend cpu --size 40x40 --frame 37 --out f37.png >/dev/null 2>&1
if cmp -s f0.png f37.png; then bad "frame 37 looks like frame 0"; else ok "frames differ"; fi

if fails_cleanly "static scene refuses --frame" 2 "does not move" --scene box --backend cpu --frame 3; then
  ok "static scene refuses --frame"
fi
if fails_cleanly "static scene refuses --animate" 2 "does not move" --scene mirrors --backend cpu --animate 4; then
  ok "static scene refuses --animate"
fi
# an instanced herd moves as the flattened one: frame N of cow4i is frame N of cow4 (the same
# triangles to rounding of the placement; tests/test_instances_cow.c compares hits)
"$bin" --scene cow4i --backend cpu --size 40x40 --frame 20 --out i20.png >/dev/null 2>&1
"$bin" --scene cow4i --backend cpu --size 40x40 --out i0.png >/dev/null 2>&1
if cmp -s i0.png i20.png; then bad "cow4i frame 20 looks like frame 0"; else ok "cow4i moves"; fi

viewer=$3
for mode in animate still; do
  extra=()
  # still: --refine off, else the second frame is the mean of two sub-pixel samples and
  # differs from the first although nothing moved (refinement: tests/viewer_refine.sh)
  [ "$mode" = animate ] && extra=(--animate 30 --frame 35) || extra=(--refine off)
  if ! "$viewer" --scene animated --local --headless --frames 2 --backend cpu --size 32x32 \
      --out "v_$mode" "${extra[@]}" >stdout.txt 2>stderr.txt; then
    bad "viewer --local $mode: $(cat stderr.txt)"
    continue
  fi
  if cmp -s "v_$mode/frame_000000.png" "v_$mode/frame_000001.png"; then moved=no; else moved=yes; fi
  want=no
  [ "$mode" = animate ] && want=yes
  if [ $moved = $want ]; then
    ok "viewer --local $mode: frames moved: $moved"
  else
    bad "viewer --local $mode: frames moved: $moved"
  fi
done
# an instanced herd moves in the viewer too (rs_renderer_update_instances)
if "$viewer" --scene cow3i --local --headless --frames 2 --backend cpu --size 64x64 \
    --animate 30 --frame 30 --out v_inst >stdout.txt 2>stderr.txt; then
  if cmp -s v_inst/frame_000000.png v_inst/frame_000001.png; then
    bad "viewer --local cow3i --animate: frames did not move"
  else
    ok "viewer --local cow3i --animate: frames moved"
  fi
else
  bad "viewer --local cow3i --animate: $(cat stderr.txt)"
fi
"$viewer" --scene box --local --headless --frames 1 --animate 30 >stdout.txt 2>stderr.txt
if [ $? -eq 2 ] && grep -q "does not move" stderr.txt; then ok "viewer refuses a static scene"; else bad "viewer static: $(cat stderr.txt)"; fi
finish
