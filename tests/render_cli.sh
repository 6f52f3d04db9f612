#!/usr/bin/env bash
# Usage: render_cli.sh RENDER_BINARY WORK_DIR. Prints "N passed, N failed" and exits non-zero
# on any failure.
source "$(dirname "$0")/cli_harness.sh"

# expect_fail NAME EXPECTED_EXIT MESSAGE_REGEX ARGS...: non-zero exit, exactly one stderr line
# matching the regex, and no PNG/JSON/PFM output left behind.
expect_fail() {
  local name=$1 code=$2 regex=$3
  shift 3
  rm -f out.png out.json out.pfm
  # cpu unless the case names a backend: auto's fallback note would be a second line.
  fails_cleanly "$name" "$code" "$regex" --backend cpu --out out.png --stats out.json --depth out.pfm "$@" || return
  if [ -e out.png ] || [ -e out.json ] || [ -e out.pfm ]; then bad "$name: left an output file"; return; fi
  if ls ./*.tmp-* >/dev/null 2>&1; then bad "$name: left a temporary file"; return; fi
  ok "$name"
}

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >tri.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n' >nan.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' >range.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' >empty.obj
printf 'this is { not a mesh\n\x01\x02\x03' >junk.obj
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n' >short.ply

expect_fail "unknown flag" 2 "unknown option '--frobnicate'" --scene box --frobnicate 1
expect_fail "missing scene flag" 2 "scene is required"
expect_fail "bad size" 2 "--size" --scene box --size 0x10
expect_fail "bad passes" 2 "--passes" --scene box --passes many
expect_fail "bad bvh" 2 "--bvh: 'octree' is not sah" --scene box --bvh octree
expect_fail "bad backend" 2 "--backend: .vulkan. is not auto.cpu.egl.osmesa" --scene box --backend vulkan
expect_fail "missing file" 1 "nope.obj" --scene nope.obj
expect_fail "malformed file" 1 "junk.obj" --scene junk.obj
expect_fail "NaN vertex" 1 "NaN|nan|finite" --scene nan.obj
expect_fail "index out of range" 1 "range|vertex|index" --scene range.obj
expect_fail "zero triangles" 1 "triangle|face|empty|mesh" --scene empty.obj
expect_fail "truncated ply" 1 "short.ply" --scene short.ply
expect_fail "too many lights" 1 "lights" --scene tri.obj --lights 9
expect_fail "unwritable output" 1 "nodir" --scene box --size 8x8 --out nodir/x.png
# The PNG and PFM are written before the stats: a failing stats file must take them back.
expect_fail "unwritable stats removes the image" 1 "nodir" --scene box --size 8x8 --stats nodir/x.json
# Renaming over a FIFO or device replaced the node itself (--out /dev/null as root).
mkfifo fifo.json
expect_fail "stats onto a fifo" 1 "fifo.json.*not a regular file" --scene box --size 8x8 --stats fifo.json
if [ -p fifo.json ]; then ok "fifo kept"; else bad "fifo replaced"; fi
# A 200-byte PLY declaring 3e8 faces made assimp reserve and touch over 8 GB.
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 300000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >lie.ply
expect_fail "ply header lying about its size" 1 "lie.ply.*face" --scene lie.ply

# A good run: PNG, PFM and a stats file with every documented key.
rm -f box.png box.json box.pfm
if "$bin" --scene box --size 32x32 --passes 2 --lights 4 --bvh paper --out box.png \
    --stats box.json --depth box.pfm >stdout.txt 2>stderr.txt; then
  missing=""
  for key in scene triangles bvh passes lights width height hit_numbers box triangle total ms build_ms; do
    grep -q "\"$key\"" box.json || missing="$missing $key"
  done
  if [ -n "$missing" ]; then bad "stats keys missing:$missing"
  elif ! grep -q '"triangles":[[:space:]]*153' box.json; then bad "box is not 153 triangles: $(cat box.json)"
  elif [ "$(head -c 8 box.png | od -An -tx1 | tr -d ' \n')" != "89504e470d0a1a0a" ]; then bad "box.png is not a PNG"
  elif [ "$(head -c 2 box.pfm)" != "Pf" ]; then bad "box.pfm is not a 1-channel PFM"
  else ok "box render writes png, pfm and stats"; fi
else
  bad "box render failed: $(cat stderr.txt)"
fi

# A user's own mesh file renders with a framed camera.
if "$bin" --scene tri.obj --size 16x16 --out tri.png >stdout.txt 2>stderr.txt && [ -s tri.png ]; then
  ok "mesh file renders"
else
  bad "mesh file render failed: $(cat stderr.txt)"
fi

# A view file may list no lights; without --lights the scene renders (ambient only).
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >dark.obj
printf '{"camera": {"eye": [0.3, 0.3, 2], "target": [0.3, 0.3, 0]}, "lights": []}' >dark.json
if "$bin" --scene dark.obj --size 8x8 --out dark.png --stats dark.json.out >stdout.txt 2>stderr.txt &&
    [ -s dark.png ] && grep -q '"lights":[[:space:]]*0' dark.json.out; then
  ok "scene without lights renders"
else
  bad "scene without lights: $(cat stderr.txt)"
fi

# The GL backends (where this build has them and a context can be made: llvmpipe in CI):
# the stats name the backend and the renderer string; a bad EGL platform fails in one line.
for backend in egl osmesa; do
  rm -f gl.png gl.json
  if "$bin" --scene box --size 32x32 --backend $backend --out gl.png --stats gl.json \
      --primary raster --shadows map:256:3 >stdout.txt 2>stderr.txt; then
    if grep -q "\"backend\":[[:space:]]*\"$backend\"" gl.json &&
        grep -q '"renderer":[[:space:]]*"[^"]' gl.json && [ -s gl.png ]; then
      ok "$backend render names backend and renderer"
    else
      bad "$backend stats: $(cat gl.json)"
    fi
  elif no_gl stderr.txt; then
    skipped "$backend not available here: $(cat stderr.txt)"
  else
    bad "$backend render failed: $(cat stderr.txt)"
  fi
done
if "$bin" --scene box --size 8x8 --backend egl >/dev/null 2>&1; then
  RS_EGL_PLATFORM=wayland expect_fail "unknown EGL platform" 1 "unknown platform 'wayland'" \
    --scene box --size 8x8 --backend egl
  # --kernels compute: the fused chain as compute dispatches, not counted (a counting frame
  # would run the separate chain), and said so; the image the fragment run's, byte for byte;
  # a chain it cannot run refused in one line with no output left.
  rm -f k.png k.json f.png
  if "$bin" --scene box --size 32x32 --backend egl --kernels compute --out k.png \
      --stats k.json >stdout.txt 2>stderr.txt &&
      grep -q ", compute kernels (hit numbers not counted)$" stdout.txt &&
      grep -q '"kernel_stage":[[:space:]]*"compute"' k.json && ! grep -q '"hit_numbers"' k.json &&
      jq -e '[.kernels[].name] | index("trace compute") != null' k.json >/dev/null &&
      "$bin" --scene box --size 32x32 --backend egl --out f.png >/dev/null 2>&1 &&
      cmp -s k.png f.png; then
    ok "egl --kernels compute renders the fragment image, not counted"
  else
    bad "egl --kernels compute: $(cat stderr.txt) $(cat stdout.txt) $(head -c 300 k.json)"
  fi
  expect_fail "compute on the separate chain" 1 "kernels compute runs the fused chain only" \
    --scene box --size 8x8 --backend egl --kernels compute --chain separate
fi

finish
