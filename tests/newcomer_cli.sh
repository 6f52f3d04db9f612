#!/usr/bin/env bash
# Usage: newcomer_cli.sh RENDER_BINARY WORK_DIR SCENE_BINARY. Issue 18 as a newcomer meets
# raystream-render and raystream-scene: one option grammar with defaults in --help, defaults
# that match the library's, outputs named on stdout and in the format their name says,
# truncated meshes refused. Prints "N passed, N failed"; fails on any failure.
source "$(dirname "$0")/cli_harness.sh"
scene_bin=$3

# expect_fail NAME EXIT REGEX ARGS...: that exit, one matching stderr line, nothing written.
expect_fail() {
  local name=$1
  rm -f ./*.png ./*.jpg ./*.json
  fails_cleanly "$@" || return
  if ls ./*.png ./*.jpg ./*.json >/dev/null 2>&1; then bad "$name: left a file"; return; fi
  ok "$name"
}
# named LINE: stdout.txt holds exactly that line.
named() { grep -qx -- "$1" stdout.txt; }

# --- 1. One grammar: every render option in --help with its values and default ---
if "$bin" --help >help.txt 2>stderr.txt && [ ! -s stderr.txt ]; then
  missing=""
  for want in "--backend auto|cpu|egl|osmesa" "--passes 1..64" "--lights 1..64|all" \
      "--size WxH" "--shadows rays|map[:RES[:FILTER]]|none" "--primary trace|raster" "--bvh sah|none|linear|paper" \
      "--nodes compact|paper" "--scene-storage auto|2d|buffer" "--threads 1..256" \
      "--reflections trace|envmap|interreflect" "[auto]" "[2]" "[all]" "[out.png]"; do
    grep -qF -- "$want" help.txt || missing="$missing '$want'"
  done
  if [ -z "$missing" ]; then ok "--help lists every render option with its default"
  else bad "--help lacks:$missing"; fi
else
  bad "--help: exit or stderr: $(cat stderr.txt)"
fi
expect_fail "--passes 0 names the range" 2 "^raystream-render: --passes: '0' is not 1..64 \(see --help\)$" \
  --scene box --passes 0
expect_fail "--lights 0 names the values" 2 "--lights: '0' is not 1..64\|all" --scene box --lights 0
expect_fail "--shadows names the values" 2 "--shadows: 'map:4' is not rays\|map\[:RES\[:FILTER\]\]" \
  --scene box --shadows map:4
# shadows none: no feeler cast (the stats count them; rays on the same frame casts some)
if "$bin" --scene box --size=8x8 --backend=cpu --shadows none --stats s.json \
    >stdout.txt 2>stderr.txt && grep -q '"shadow_rays":[[:space:]]*0,' s.json &&
    grep -q '"shadows":[[:space:]]*"none"' s.json &&
    "$bin" --scene box --size=8x8 --backend=cpu --shadows rays --stats s.json \
    >stdout.txt 2>stderr.txt && grep -q '"shadow_rays":[[:space:]]*[1-9]' s.json
then ok "--shadows none casts no feeler"
else bad "--shadows none: $(cat stderr.txt) $(cat s.json)"; fi
expect_fail "--size 0x8 names the form" 2 "--size: '0x8' is not WxH" --scene box --size 0x8
expect_fail "a value missing" 2 "option --passes needs a value" --scene box --passes
if "$bin" --scene box --size=8x8 --passes=1 --lights=2 --backend=cpu --stats s.json \
    >stdout.txt 2>stderr.txt && grep -q '"passes":[[:space:]]*1' s.json &&
    grep -q '"lights":[[:space:]]*2' s.json; then ok "--key=value is the same as --key value"
else bad "--key=value: $(cat stderr.txt)"; fi

# --- 2. Defaults that mean one thing (the pixel comparison with the library is test_defaults) ---
if "$bin" --scene box --size 8x8 --stats d.json >stdout.txt 2>stderr.txt &&
    grep -q '"lights":[[:space:]]*4' d.json && grep -q '"passes":[[:space:]]*2' d.json; then
  ok "no --lights uses all four of box's lights, as a zero rs_render_desc does"
else bad "default lights: $(grep -o '"lights":[^,]*' d.json) $(cat stderr.txt)"; fi
backend=$(sed -n 's/.*"backend":[[:space:]]*"\([a-z]*\)".*/\1/p' d.json)
if [ "$backend" = cpu ]; then
  if grep -q "auto: .*rendering on cpu" stderr.txt; then ok "auto fell back to cpu and said so"
  else bad "auto fell back to cpu silently: $(cat stderr.txt)"; fi
elif [ -n "$backend" ] && [ ! -s stderr.txt ]; then ok "auto picked the GL backend $backend"
else bad "auto: backend '$backend', stderr $(cat stderr.txt)"; fi

# --- 5. Outputs named on stdout, in the format their name says ---
if "$bin" --scene box --size 8x8 --backend cpu >stdout.txt 2>stderr.txt && named "wrote out.png" &&
    [ "$(head -c 8 out.png | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; then
  ok "without --out: out.png, named on stdout"
else bad "without --out: $(cat stdout.txt stderr.txt)"; fi
if "$bin" --scene box --size 8x8 --backend cpu --out a.png --stats a.json --depth a.pfm \
    >stdout.txt 2>stderr.txt && named "wrote a.png" && named "wrote a.json" && named "wrote a.pfm"; then
  ok "every output named"
else bad "outputs not named: $(cat stdout.txt stderr.txt)"; fi
if "$bin" --scene box --size 16x16 --backend cpu --out x.jpg >stdout.txt 2>stderr.txt &&
    named "wrote x.jpg" && [ "$(head -c 3 x.jpg | od -An -tx1 | tr -d ' \n')" = ffd8ff ]; then
  ok "--out x.jpg writes a JPEG"
else bad "--out x.jpg: $(head -c 8 x.jpg | od -An -tx1) $(cat stderr.txt)"; fi
expect_fail "--out x.gif refused" 2 "--out: 'x.gif' does not end in .png, .jpg or .jpeg" \
  --scene box --size 8x8 --out x.gif

# --- 4. Never silent success: a body shorter than its header (or OBJ line) is refused ---
head='ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n'
z='\x00\x00\x00\x00' one='\x00\x00\x80\x3f'
{ printf "$head"; printf "$z$z$z$one$z$z$z$one$z$one$one$z"
  printf '\x03\x00\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00'; } >cut.ply
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n' >cut_ascii.ply
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4' >cut.obj
expect_fail "binary PLY with 1 of 2 faces" 1 "cut\.ply: PLY data ends after 1 of the 2 'face' elements" \
  --scene cut.ply --size 8x8 --backend cpu
expect_fail "ASCII PLY with 1 of 2 faces" 1 "cut_ascii\.ply: PLY data ends after 1 of the 2 'face'" \
  --scene cut_ascii.ply --size 8x8 --backend cpu
expect_fail "OBJ cut mid-face" 1 "cut\.obj: line 6: face with 2 vertices" \
  --scene cut.obj --size 8x8 --backend cpu
bin=$scene_bin
expect_fail "scene --info refuses the cut PLY" 1 "cut\.ply: PLY data ends after 1 of the 2 'face'" \
  --scene cut.ply --info
expect_fail "scene --info refuses the cut OBJ" 1 "cut\.obj: line 6: face with 2 vertices" \
  --scene cut.obj --info

# --- raystream-scene: the same grammar, mirrors listed, exports named ---
if "$bin" --help >help.txt 2>&1 && grep -q mirrors help.txt; then ok "scene --help lists mirrors"
else bad "scene --help: $(cat help.txt)"; fi
if "$bin" --scene box --out-obj b.obj >stdout.txt 2>stderr.txt && named "wrote b.obj" &&
    named "wrote b.mtl" && named "wrote b.json" && [ -s b.mtl ]; then
  ok "scene export names its three files"
else bad "scene export: $(cat stdout.txt stderr.txt)"; fi
expect_fail "scene: unknown option" 2 "^raystream-scene: unknown option '--bogus' \(see --help\)$" \
  --scene box --bogus

finish
