#!/usr/bin/env bash
# The seed paper's Tables 1, 2 and 3 regenerated on this machine, the paper's figures beside
# ours, machine and renderer named, progress on stderr. Calls the built tools:
#   Table 1  raystream-bench (hit numbers per builder, 2 passes)
#   Table 2  raystream-bench --table 2
#   Table 3  the mirrors scene at 5 passes: classic (rasterized primaries) and
#            inter-reflection environment mapping (2 bounces) and the ray tracer on the
#            backend, and the CPU reference (raystream-bench --times, read from its --json)
set -euo pipefail
usage() {
  cat <<'EOF'
usage: tools/paper-tables.sh [--quick] [--build DIR] [--backend egl|osmesa|cpu] [--out FILE.md]
  The paper's Tables 1-3 beside ours, as Markdown (stdout unless --out; progress on stderr).
  --quick          box (and mirrors) at 32x32, one frame: the plumbing (CI), not speed
  --build DIR      the build folder (default: $RS_BUILD_DIR, else build/ in the source tree)
  --backend NAME   the backend of Tables 2 and 3 (default: egl)
  --out FILE.md    write the tables there, all or nothing (its folder must exist; checked
                   before any work)
EOF
}
die() { echo "paper-tables: $*" >&2; exit "${code:-1}"; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RS_BUILD_DIR:-$root/build}
backend=egl
quick=0
out=""
while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --quick) quick=1; shift ;;
    --build|--backend|--out)
      [ $# -ge 2 ] && [ -n "$2" ] || code=2 die "$1 needs a value (try --help)"
      case $1 in --build) build=$2 ;; --backend) backend=$2 ;; --out) out=$2 ;; esac
      shift 2 ;;
    *) code=2 die "unknown option '$1' (try --help)" ;;
  esac
done
# The output is checked before minutes of work, not after: a folder, a missing folder or
# one we cannot write is refused now, and a device or FIFO is never replaced. The tables
# go to a temporary file beside the target, renamed over it only when complete.
outtmp="" tmp=""
trap 'rm -rf "$tmp"; [ -z "$outtmp" ] || rm -f "$outtmp"' EXIT
if [ -n "$out" ]; then
  [ -d "$out" ] && die "--out $out is a folder; give a file name (e.g. $out/tables.md)"
  [ -e "$out" ] && [ ! -f "$out" ] && die "--out $out exists and is not a regular file"
  outdir=$(dirname -- "$out")
  [ -d "$outdir" ] || die "cannot write $out: no folder $outdir"
  outtmp=$(mktemp "$out.tmp-XXXXXX" 2>/dev/null) || die "cannot write $out: folder $outdir is not writable"
fi
bench=$build/tools/bench/raystream-bench
[ -x "$bench" ] || die "$bench not built (cmake --build $build)"
command -v jq >/dev/null || die "jq is needed to read raystream-bench --json (tools/deps.sh)"
if [ "$quick" = 1 ]; then
  size=32; frames=1; t1=(--scene box --size 32 --flat-size 16 --repeats 1)
else
  size=512; frames=5; t1=()
fi
# Table 3: inter-reflection bounces (the paper does not give its number).
bounces3=2
step() { echo "paper-tables: $*" >&2; }
tmp=$(mktemp -d)

# times_row SCENE PASSES PRIMARY [BACKEND [REFLECTIONS]]: "fps hits" of one
# raystream-bench --times run, read from its JSON; the renderer string is kept for the
# header.
times_row() {
  local scene=$1 passes=$2 primary=$3 be=${4:-$backend} refl=${5:-trace}
  "$bench" --times --backend "$be" --size "$size" --repeats "$frames" --passes "$passes" \
    --lights 1 --primary "$primary" --reflections "$refl" --json "$tmp/times.json" \
    "$scene" >"$tmp/times.txt" || die "raystream-bench --times $scene failed"
  jq -r '.rows[0].renderer' "$tmp/times.json" >"$tmp/renderer-$be"
  jq -r '.rows[0] | "\(.fps * 100 | round / 100) \(.hit_numbers * 10 | round / 10)"' \
    "$tmp/times.json" || die "cannot read $tmp/times.json"
}

{
  echo "# The paper's tables on this machine"
  echo
  echo "Machine: $(uname -m), $(nproc) cores, $(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -1);"
  echo "load average at the start: $(cut -d' ' -f1-3 /proc/loadavg). Paper: NVIDIA GeForce"
  echo "8800-class GPU, 3.2 GHz CPU, 512x512. Ours: ${size}x${size}$([ "$quick" = 1 ] && echo ' (--quick: plumbing only)')."
  echo
} >"$tmp/out.md"

step "Table 1 (raystream-bench ${t1[*]})"
{
  echo "## Table 1: hit numbers, 2 passes (raystream-bench, CPU reference counting)"
  echo
  "$bench" --passes 2 "${t1[@]}"
  echo
} >>"$tmp/out.md"

step "Table 2 (raystream-bench --table 2 --backend $backend)"
t2=(--table 2 --backend "$backend")
[ "$quick" = 1 ] && t2+=(--scene box --size 32 --repeats 1)
{ echo "## Table 2 (raystream-bench --table 2)"; echo; "$bench" "${t2[@]}"; echo; } >>"$tmp/out.md"

step "Table 3: mirrors, 5 passes, $backend"
row=$(times_row mirrors 5 trace)
fps3=${row% *} hits3=${row#* }
step "Table 3: mirrors, classic environment mapping (rasterized primaries), $backend"
row=$(times_row mirrors 5 raster "$backend" envmap)
fpsenv=${row% *}
step "Table 3: mirrors, inter-reflection environment mapping ($bounces3 bounces), $backend"
row=$(times_row mirrors 5 trace "$backend" "interreflect:$bounces3")
fpsinter=${row% *}
step "Table 3: mirrors, 5 passes, cpu reference"
row=$(times_row mirrors 5 trace cpu)
fpscpu=${row% *}
{
  echo "## Table 3: environment mapping against ray tracing, mirrors scene (25,254 triangles), 5 passes, 1 light"
  echo
  echo "| | classic env map | inter-reflection env maps | ray tracer ($backend) | CPU reference |"
  echo "|---|---:|---:|---:|---:|"
  echo "| paper, fps | 101.74 | 3.46 | 12.79 | — |"
  echo "| ours, fps | $fpsenv | $fpsinter ($bounces3 bounces) | $fps3 (hit numbers $hits3) | $fpscpu |"
  echo
  echo "Classic environment mapping: rasterized primary hits (the paper's classic method is the"
  echo "GPU's rasterizer with a cube map; the ray tracer column traces its primaries), exact"
  echo "shadow feelers, one cube map captured at set_scene from the scene's centre, read by the"
  echo "reflected rays."
  echo "Inter-reflection: a cube map per mirror object (4), captured every frame from its"
  echo "bounding-sphere centre, $bounces3 bounces; rays leaving an object read its own map."
  echo
  echo "Renderers: $backend: $(cat "$tmp/renderer-$backend"); cpu: $(cat "$tmp/renderer-cpu")."
  echo
} >>"$tmp/out.md"

if [ -n "$out" ]; then
  cat "$tmp/out.md" >"$outtmp" || die "cannot write $out"
  mv -f "$outtmp" "$out" || die "cannot write $out"
  outtmp=""
  echo "$out"
  step "wrote $out"
else
  cat "$tmp/out.md" || die "cannot write the tables to standard output"
fi
