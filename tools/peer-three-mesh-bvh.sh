#!/usr/bin/env bash
# Primary rays against three-mesh-bvh's GLSL traversal on the same driver (docs/benchmarks.md,
# "Primary rays against three-mesh-bvh"). Installs three and three-mesh-bvh with npm into a
# temporary folder for this run only (never a dependency of the build), and per scene:
# raystream-peer-tmb --mesh-out (the scene's triangles), build_bvh.mjs (their MeshBVH and
# MeshBVHUniformStruct textures, their GLSL chunks), raystream-peer-tmb --bvh (ours and theirs
# alternately on the same camera rays, each checked against the CPU reference's primary hits).
# Ours is the hits-only kernel (rs_render_desc.hits_only); sep_ms and "sep ratio" are the
# separate chain's raygen + intersect, timed in the same alternation.
# Prints one table at the end; on any failure one line on stderr, nothing on stdout, exit 1
# (2 for a usage error).
set -euo pipefail
usage() {
  cat <<'EOF2'
usage: tools/peer-three-mesh-bvh.sh [options] [SCENE...]
  Primary rays (closest hit, Mrays/s), ours against three-mesh-bvh's GLSL traversal, on the
  same EGL driver, triangles and camera rays; SCENE... default: cow1 cow9 cow17.
  --build DIR        the build folder (default: $RS_BUILD_DIR, else build/; Release for figures)
  --repeats N        timed frames of each, alternately (default 7; the median is shown)
  --size N           image side in pixels (default 512)
  --strategy S       three-mesh-bvh's split strategy: center (its default), average or sah
  --nodes N          our node layout and orders (default compact:octant; raystream-render's
                     --nodes values)
  --version V        three-mesh-bvh's version (default 0.9.17; three: --three-version, 0.187.0)
  --three-version V
EOF2
}
die() { echo "peer-three-mesh-bvh: $*" >&2; exit "${code:-1}"; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RS_BUILD_DIR:-$root/build}
repeats=7 size=512 strategy=center nodes=compact:octant tmb_version=0.9.17 three_version=0.187.0
scenes=()
while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --build|--repeats|--size|--strategy|--nodes|--version|--three-version)
      [ $# -ge 2 ] && [ -n "$2" ] || code=2 die "$1 needs a value (try --help)"
      case $1 in
        --build) build=$2 ;; --repeats) repeats=$2 ;; --size) size=$2 ;;
        --strategy) strategy=$2 ;; --nodes) nodes=$2 ;;
        --version) tmb_version=$2 ;; --three-version) three_version=$2 ;;
      esac
      shift 2 ;;
    -*) code=2 die "unknown option '$1' (try --help)" ;;
    *) scenes+=("$1"); shift ;;
  esac
done
case $strategy in center|average|sah) ;; *) code=2 die "--strategy $strategy: not center, average or sah" ;; esac
[ ${#scenes[@]} -gt 0 ] || scenes=(cow1 cow9 cow17)
harness=$build/tools/bench/three_mesh_bvh/raystream-peer-tmb
[ -x "$harness" ] || die "$harness not built (cmake --build $build; it needs the egl backend)"
command -v node >/dev/null && command -v npm >/dev/null ||
  die "node and npm are needed to run three-mesh-bvh (nothing was measured)"

tmp=$(mktemp -d "${TMPDIR:-/tmp}/peer-tmb.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
# The packages live in $tmp only (--prefix: npm would otherwise look upwards for a project to
# install into): no package.json, lock file or node_modules in the tree.
if ! (cd "$tmp" && npm install --prefix "$tmp" --no-save --no-package-lock --no-audit --no-fund \
      --fetch-retries=0 --fetch-timeout=30000 "three@$three_version" "three-mesh-bvh@$tmb_version") \
      >"$tmp/npm.log" 2>&1; then
  why=$(grep -m1 -E 'npm (ERR|error) (code|network|[0-9]{3})|E[A-Z]{4,}' "$tmp/npm.log" | tr -s ' ' || true)
  die "npm cannot install three-mesh-bvh@$tmb_version and three@$three_version (${why:-see npm}); nothing was measured"
fi
cp "$root/tools/bench/three_mesh_bvh/build_bvh.mjs" "$tmp/"
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
rows=()
for scene in "${scenes[@]}"; do
  mkdir -p "$tmp/$scene"
  "$harness" --scene "$scene" --mesh-out "$tmp/$scene.mesh" >/dev/null 2>"$tmp/err.txt" ||
    die "$scene: $(head -n1 "$tmp/err.txt")"
  (cd "$tmp" && node build_bvh.mjs "$scene.mesh" "$scene" "$strategy") 2>"$tmp/err.txt" ||
    die "$scene: three-mesh-bvh's build failed: $(head -n1 "$tmp/err.txt")"
  "$harness" --scene "$scene" --bvh "$tmp/$scene" --size "${size}x${size}" --repeats "$repeats" \
    --nodes "$nodes" >"$tmp/out.txt" 2>"$tmp/err.txt" || die "$scene: $(head -n1 "$tmp/err.txt")"
  # "scene S size WxH rays N frames F ours_ms A theirs_ms B ... theirs_agree Q": key value pairs
  declare -A v=()
  read -r -a f <"$tmp/out.txt"
  for ((i = 0; i + 1 < ${#f[@]}; i += 2)); do v[${f[i]}]=${f[i + 1]}; done
  for k in ours_ms theirs_ms ours_mrays theirs_mrays ratio ratio_min ratio_max ours_agree theirs_agree \
    separate_ms separate_ratio separate_agree; do
    [ -n "${v[$k]:-}" ] || die "$scene: the harness printed no $k"
  done
  info=$(cat "$tmp/$scene/info.txt")
  rows+=("$(printf '%-6s %9s %9s %11s %13s %6s %11s %10s %10s %6s %9s %7s %9s' "$scene" "${v[ours_ms]}" \
    "${v[theirs_ms]}" "${v[ours_mrays]}" "${v[theirs_mrays]}" "${v[ratio]}" \
    "${v[ratio_min]}-${v[ratio_max]}" "${v[ours_agree]}" "${v[theirs_agree]}" "$(awk '{print $6}' <<<"$info")" \
    "$(awk '{print $8}' <<<"$info")" "${v[separate_ms]}" "${v[separate_ratio]}")")
  renderer=$(sed -n 's/^renderer //p' "$tmp/out.txt")
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
echo "three-mesh-bvh $tmb_version (three $three_version, strategy $strategy) against raystream ($nodes nodes) on $renderer, ${size}x${size}, primary closest-hit rays, median of $repeats alternating frames; load $load_before before, $load_after after"
printf '%-6s %9s %9s %11s %13s %6s %11s %10s %10s %6s %9s %7s %9s\n' scene ours_ms their_ms "ours Mray/s" \
  "theirs Mray/s" ratio "per frame" "ours agree" "their agr." nodes "build ms" sep_ms "sep ratio"
printf '%s\n' "${rows[@]}"
