#!/usr/bin/env bash
# Usage: peer_tmb_cli.sh HARNESS WORK_DIR SCRIPT BUILD_DIR. raystream-peer-tmb, the harness of
# tools/peer-three-mesh-bvh.sh, without the network: the box scene's mesh written for
# build_bvh.mjs; a fixture in the layout build_bvh.mjs writes (one leaf holding every
# triangle, in reverse order, and a brute-force GLSL stand-in for three-mesh-bvh's chunks
# with the same BVH struct and bvhIntersectFirstHit) traced on the same driver and checked
# against the CPU reference; the same fixture with a wrong slot map must disagree; broken
# fixtures refused in one line. The script must refuse in one line, with nothing on stdout,
# when npm cannot install the package. Exits 77 (skipped) when no EGL context can be made.
source "$(dirname "$0")/cli_harness.sh"
script=$3
build=$4

# m.mesh -> DIR: the fixture (perl is in every Debian install, as bash is).
make_fixture() { # MESH DIR SLOTS(reverse|identity)
  mkdir -p "$2"
  perl -e '
    use strict; my ($mesh, $dir, $order) = @ARGV;
    open(my $in, "<:raw", $mesh) or die "$mesh: $!"; local $/; my $b = <$in>;
    my ($magic, $nv, $nt) = unpack("a8 V V", $b);
    my @p = unpack("f<" . 3 * $nv, substr($b, 16, 12 * $nv));
    my @ix = unpack("V" . 3 * $nt, substr($b, 16 + 12 * $nv));
    sub put { my ($name, $data) = @_; open(my $o, ">:raw", "$dir/$name") or die; print $o $data; }
    my $dv = int(sqrt($nv)); $dv++ while $dv * $dv < $nv;
    my $dt = int(sqrt($nt)); $dt++ while $dt * $dt < $nt;
    my (@lo, @hi) = ((1e30) x 3); @hi = ((-1e30) x 3);
    my $pos = "";
    for my $v (0 .. $dv * $dv - 1) {
      my @xyz = $v < $nv ? @p[3 * $v .. 3 * $v + 2] : (0, 0, 0);
      if ($v < $nv) { for my $a (0 .. 2) { $lo[$a] = $xyz[$a] if $xyz[$a] < $lo[$a];
                                           $hi[$a] = $xyz[$a] if $xyz[$a] > $hi[$a]; } }
      $pos .= pack("f<4", @xyz, 0);
    }
    my ($idx, $slots) = ("", "");
    for my $s (0 .. $dt * $dt - 1) {
      my $t = $nt - 1 - $s;  # the slots hold the triangles in reverse order
      $idx .= $s < $nt ? pack("V4", @ix[3 * $t .. 3 * $t + 2], 0) : pack("V4", 0, 0, 0, 0);
      $slots .= pack("V", $order eq "reverse" ? $t : $s) if $s < $nt;
    }
    put("position.bin", $pos); put("index.bin", $idx); put("slots.bin", $slots);
    put("bvhBounds.bin", pack("f<16", @lo, 0, @hi, 0, (0) x 8));
    put("bvhContents.bin", pack("V2", 0xffff0000 | $nt, 0));
    put("textures.txt", "index RGBA32UI $dt $dt\nposition RGBA32F $dv $dv\n" .
                        "bvhBounds RGBA32F 2 2\nbvhContents RG32UI 1 1\n");
  ' "$1" "$2" "$3"
  cat >"$2/bvh.glsl" <<'GLSL'
#define INFINITY 1e20
struct BVH {
  usampler2D index;
  sampler2D position;
  sampler2D bvhBounds;
  usampler2D bvhContents;
};
vec4 fx_fetch(sampler2D t, uint i) {
  uint w = uint(textureSize(t, 0).x);
  return texelFetch(t, ivec2(i % w, i / w), 0);
}
uvec4 fx_ufetch(usampler2D t, uint i) {
  uint w = uint(textureSize(t, 0).x);
  return texelFetch(t, ivec2(i % w, i / w), 0);
}
bool fx_first_hit(sampler2D pos, usampler2D idx, usampler2D contents, vec3 ro, vec3 rd,
                  inout uvec4 face, inout float dist) {
  uvec2 leaf = fx_ufetch(contents, 0u).xy;
  float best = INFINITY;
  bool found = false;
  for (uint i = leaf.y; i < leaf.y + (leaf.x & 0xffffu); ++i) {
    uvec3 t = fx_ufetch(idx, i).xyz;
    vec3 a = fx_fetch(pos, t.x).xyz, e1 = fx_fetch(pos, t.y).xyz - a,
         e2 = fx_fetch(pos, t.z).xyz - a, p = cross(rd, e2), s = ro - a, q = cross(s, e1);
    float det = dot(e1, p);
    if (abs(det) < 1e-20) continue;
    float u = dot(s, p) / det, v = dot(rd, q) / det, d = dot(e2, q) / det;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && d > 0.0 && d < best) {
      best = d;
      face = uvec4(t, i);
      found = true;
    }
  }
  dist = best;
  return found;
}
#define bvhIntersectFirstHit(bvh, ro, rd, face, normal, bary, side, dist) \
  fx_first_hit(bvh.position, bvh.index, bvh.bvhContents, ro, rd, face, dist)
GLSL
}

# value KEY: the number after KEY in out.txt's first line
value() { awk -v k="$1" '{for (i = 1; i < NF; i += 2) if ($i == k) print $(i + 1)}' out.txt | head -n1; }

# The mesh: "wrote FILE", 16 header bytes and 12 per vertex and per triangle.
if "$bin" --scene box --mesh-out m.mesh >out.txt 2>err.txt && grep -qx "wrote m.mesh" out.txt &&
   [ "$(head -c 8 m.mesh | tr -d '\0')" = RSMESH1 ]; then
  nv=$(od -A n -t u4 -j 8 -N 4 m.mesh | tr -d ' ') nt=$(od -A n -t u4 -j 12 -N 4 m.mesh | tr -d ' ')
  size=$(stat -c %s m.mesh)
  if [ "$size" -eq $((16 + 12 * nv + 12 * nt)) ] && [ "$nt" -gt 0 ]; then ok "mesh ($nv vertices, $nt triangles)"
  else bad "mesh: $size bytes for $nv vertices, $nt triangles"; fi
else bad "mesh: $(head -c 300 err.txt)"; fi

make_fixture m.mesh fx reverse
if ! "$bin" --scene box --bvh fx --size 32x32 --repeats 2 >out.txt 2>err.txt; then
  if grep -qiE "egl|GLES 3 context|not part of this build" err.txt; then
    echo "skipped: $(head -c 200 err.txt)"; exit 77
  fi
  bad "fixture run: $(head -c 300 err.txt)"
else
  # both tracers (ours: the hits-only kernel and the separate chain) hit the CPU reference's
  # triangle in (nearly) every pixel; the fixture's reversed slots are mapped back, so the
  # ids are the scene's
  ours=$(value ours_agree) theirs=$(value theirs_agree) sep=$(value separate_agree)
  if awk -v a="$ours" -v b="$theirs" -v c="$sep" 'BEGIN {exit !(a >= 99.0 && b >= 99.0 && c >= 99.0)}' &&
     [ "$(value rays)" = 1024 ] && [ "$(value frames)" = 2 ] && grep -q '^renderer .' out.txt &&
     awk -v a="$(value ours_ms)" -v b="$(value separate_ms)" 'BEGIN {exit !(a > 0 && b > 0)}'; then
    ok "fixture: ours $ours % (separate chain $sep %), theirs $theirs % of the CPU reference's hits"
  else bad "fixture: $(tr '\n' ' ' <out.txt)"; fi
fi
# the same fixture with the slots left unmapped: the check notices
make_fixture m.mesh fx_wrong identity
if "$bin" --scene box --bvh fx_wrong --size 32x32 --repeats 1 >out.txt 2>err.txt &&
   awk -v b="$(value theirs_agree)" 'BEGIN {exit !(b < 90.0)}'; then
  ok "wrong slot map disagrees ($(value theirs_agree) %)"
else bad "wrong slot map: $(tr '\n' ' ' <out.txt) $(head -c 200 err.txt)"; fi

# broken fixtures and usage: one line, exit 1 (input) or 2 (usage)
mkdir -p empty
fails_cleanly "empty folder" 1 "empty/slots.bin: not [0-9]+ triangle slots" --scene box --bvh empty && ok "empty folder"
cp fx/slots.bin empty/
fails_cleanly "no textures.txt" 1 "empty/textures.txt: cannot read" --scene box --bvh empty && ok "no textures.txt"
cp -r fx fx_bad && sed -i 's/^position RGBA32F/position RGB16F/' fx_bad/textures.txt
fails_cleanly "unknown format" 1 "is not a texture of BVH" --scene box --bvh fx_bad && ok "unknown format"
cp -r fx fx_short && head -c 100 fx/index.bin >fx_short/index.bin
fails_cleanly "short texels" 1 "index.bin: 100 bytes" --scene box --bvh fx_short && ok "short texels"
cp -r fx fx_glsl && echo 'void main() {' >>fx_glsl/bvh.glsl
fails_cleanly "broken chunks" 1 "the peer's shader does not compile" --scene box --bvh fx_glsl && ok "broken chunks"
fails_cleanly "neither mode" 2 "one of --mesh-out or --bvh" --scene box && ok "neither mode"
fails_cleanly "both modes" 2 "one of --mesh-out or --bvh" --scene box --bvh fx --mesh-out x && ok "both modes"

# The script without the network: npm failing as an unreachable registry does.
mkdir -p fakebin
printf '#!/bin/sh\necho "npm error code ECONNREFUSED" >&2\nexit 1\n' >fakebin/npm
printf '#!/bin/sh\nexit 0\n' >fakebin/node
chmod +x fakebin/npm fakebin/node
PATH="$PWD/fakebin:$PATH" bash "$script" --build "$build" box >stdout.txt 2>stderr.txt
rc=$?
if [ "$rc" -eq 1 ] && [ ! -s stdout.txt ] && [ "$(wc -l <stderr.txt)" -eq 1 ] &&
   grep -q "npm cannot install three-mesh-bvh@0.9.17.*ECONNREFUSED.*nothing was measured" stderr.txt; then
  ok "script refuses without the registry"
else bad "script without the registry: exit $rc, stdout '$(head -c 200 stdout.txt)', stderr '$(head -c 300 stderr.txt)'"; fi
bash "$script" --build "$build" --strategy best box >stdout.txt 2>stderr.txt
rc=$?
if [ "$rc" -eq 2 ] && [ ! -s stdout.txt ] && [ "$(wc -l <stderr.txt)" -eq 1 ]; then ok "script usage error"
else bad "script usage error: exit $rc, $(head -c 300 stderr.txt)"; fi
finish
