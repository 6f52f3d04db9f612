#!/usr/bin/env bash
# The seed paper's Tables 1, 2 and 3 regenerated on this machine, the paper's figures beside
# ours, machine and renderer named, progress on stderr. Calls the built tools:
#   Table 1  raystream-bench (hit numbers per builder, 2 passes)
#   Table 2  raystream-bench --table 2
#   Table 3  the mirrors scene at 5 passes: classic (rasterized primaries; with exact
#            feelers, and without shadows as the paper's) and inter-reflection environment
#            mapping (2 bounces) and the ray tracer on the backend, each with its error
#            against the CPU reference tracer, and the CPU reference (raystream-bench
#            --times [--error], read from its --json)
set -euo pipefail
usage() {
  cat <<'EOF'
usage: tools/paper-tables.sh [--quick] [--build DIR] [--backend egl|osmesa|cpu] [--rounds N] [--out FILE.md]
  The paper's Tables 1-3 beside ours, as Markdown (stdout unless --out; progress on stderr).
  --quick          box (and mirrors) at 32x32, one frame: the plumbing (CI), not speed
  --rounds N       Table 3: N rounds of its four backend columns, alternating within each
                   round; fps the median of the rounds, ratios the median of the per-round
                   ratios (1..64; default 7, --quick 1)
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
rounds=""
while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --quick) quick=1; shift ;;
    --build|--backend|--out|--rounds)
      [ $# -ge 2 ] && [ -n "$2" ] || code=2 die "$1 needs a value (try --help)"
      case $1 in
        --build) build=$2 ;; --backend) backend=$2 ;; --out) out=$2 ;;
        --rounds)
          [[ "$2" =~ ^[0-9]+$ ]] && [ "$2" -ge 1 ] && [ "$2" -le 64 ] ||
            code=2 die "--rounds: '$2' is not a whole number in 1..64"
          rounds=$2 ;;
      esac
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
  size=32; frames=1; t1=(--scene box --size 32 --flat-size 16 --repeats 1); rounds=${rounds:-1}
else
  size=512; frames=5; t1=(); rounds=${rounds:-7}
fi
# Table 3: inter-reflection bounces (the paper does not give its number).
bounces3=2
step() { echo "paper-tables: $*" >&2; }
tmp=$(mktemp -d)

# times_row SCENE PASSES PRIMARY [BACKEND [REFLECTIONS [SHADOWS [--error]]]]: "fps hits"
# of one raystream-bench --times run, read from its JSON, and with --error "PSNR max bad%"
# of its first frame against the CPU reference tracer (raystream-bench --error: traced
# primaries and reflections, exact feelers; PSNR "inf" for no difference); the renderer
# string is kept for the header.
times_row() {
  local scene=$1 passes=$2 primary=$3 be=${4:-$backend} refl=${5:-trace} sh=${6:-rays}
  local error=(${7:+"$7"})
  "$bench" --times --backend "$be" --size "$size" --repeats "$frames" --passes "$passes" \
    --lights 1 --primary "$primary" --reflections "$refl" --shadows "$sh" "${error[@]}" \
    --json "$tmp/times.json" "$scene" >"$tmp/times.txt" ||
    die "raystream-bench --times $scene failed"
  jq -r '.rows[0].renderer' "$tmp/times.json" >"$tmp/renderer-$be"
  jq -r '.rows[0] | "\(.fps * 100 | round / 100) \(.hit_numbers * 10 | round / 10)" +
         (if .error then " \(if .error.psnr_db == null then "inf"
                             else .error.psnr_db * 10 | round / 10 end)" +
             " \(.error.max_abs_error * 1000 | round / 1000)" +
             " \(.error.bad_share * 100000 | round / 1000)%" else "" end)' \
    "$tmp/times.json" || die "cannot read $tmp/times.json"
}
# error PSNR MAX BAD: one error cell ("31.2 dB, max 0.512, 2.3% off").
error() {
  if [ "$1" = inf ]; then echo "identical"; else echo "$1 dB, max $2, $3 off"; fi
}
# ratio A B: A / B to two decimals ("—" when B is 0).
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0) printf "%.2f", a / b; else printf "—" }'; }
# median X...: the median of the numbers given ("—" is skipped; "—" when none is left).
median() {
  printf '%s\n' "$@" | grep -E '^[0-9.]+$' | sort -g |
    awk '{ a[NR] = $1 } END { if (NR == 0) printf "—"
                              else if (NR % 2) printf "%s", a[(NR + 1) / 2]
                              else printf "%.2f", (a[NR / 2] + a[NR / 2 + 1]) / 2 }'
}
# range X...: "lowest–highest" of the numbers given.
range() {
  printf '%s\n' "$@" | grep -E '^[0-9.]+$' | sort -g | sed -n '1p;$p' | paste -sd'-' | sed 's/-/–/'
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

# Each row: fps hits [PSNR max bad%] (times_row). The four backend columns alternate
# within each round, so that a change of the machine's speed (other work, a shared host's
# steal time) falls on every column alike; the error is the first round's (the images do
# not change between rounds).
t3_fps=() env_fps=() none_fps=() inter_fps=() env_r=() none_r=() inter_r=()
load3=$(cut -d' ' -f1-3 /proc/loadavg)
for ((r = 1; r <= rounds; r++)); do
  e=""
  [ "$r" = 1 ] && e=--error
  step "Table 3, round $r of $rounds: mirrors, 5 passes, $backend"
  read -r f h d m b <<<"$(times_row mirrors 5 trace "$backend" trace rays $e)"
  [ "$r" = 1 ] && { hits3=$h db3=$d max3=$m bad3=$b; }
  t3_fps+=("$f")
  step "Table 3, round $r of $rounds: mirrors, classic environment mapping (rasterized primaries), $backend"
  read -r fe _ d m b <<<"$(times_row mirrors 5 raster "$backend" envmap rays $e)"
  [ "$r" = 1 ] && { dbenv=$d maxenv=$m badenv=$b; }
  step "Table 3, round $r of $rounds: mirrors, classic environment mapping, no shadows (the paper's), $backend"
  read -r fn _ d m b <<<"$(times_row mirrors 5 raster "$backend" envmap none $e)"
  [ "$r" = 1 ] && { dbnone=$d maxnone=$m badnone=$b; }
  step "Table 3, round $r of $rounds: mirrors, inter-reflection environment mapping ($bounces3 bounces), $backend"
  read -r fr _ d m b <<<"$(times_row mirrors 5 trace "$backend" "interreflect:$bounces3" rays $e)"
  [ "$r" = 1 ] && { dbinter=$d maxinter=$m badinter=$b; }
  env_fps+=("$fe") none_fps+=("$fn") inter_fps+=("$fr")
  env_r+=("$(ratio "$fe" "$f")") none_r+=("$(ratio "$fn" "$f")") inter_r+=("$(ratio "$fr" "$f")")
done
load3="$load3 at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end"
fps3=$(median "${t3_fps[@]}") fpsenv=$(median "${env_fps[@]}")
fpsnone=$(median "${none_fps[@]}") fpsinter=$(median "${inter_fps[@]}")
step "Table 3: mirrors, 5 passes, cpu reference"
read -r fpscpu _ <<<"$(times_row mirrors 5 trace cpu)"
{
  echo "## Table 3: environment mapping against ray tracing, mirrors scene (25,254 triangles), 5 passes, 1 light"
  echo
  echo "| | classic env map | classic env map, reflection only (the paper's effects: no shadows) | inter-reflection env maps | ray tracer ($backend) | CPU reference |"
  echo "|---|---:|---:|---:|---:|---:|"
  echo "| paper, fps | — | 101.74 | 3.46 | 12.79 | — |"
  echo "| paper, effects | — | approximate reflection | inter-reflection | inter- and self-reflection, shadows | — |"
  echo "| ours, fps | $fpsenv | $fpsnone | $fpsinter ($bounces3 bounces) | $fps3 (hit numbers $hits3) | $fpscpu |"
  echo "| ours, fps / the ray tracer's | $(median "${env_r[@]}") | $(median "${none_r[@]}") | $(median "${inter_r[@]}") | 1 | $(ratio "$fpscpu" "$fps3") |"
  echo "| ours, error against the CPU reference tracer | $(error "$dbenv" "$maxenv" "$badenv") | $(error "$dbnone" "$maxnone" "$badnone") | $(error "$dbinter" "$maxinter" "$badinter") | $(error "$db3" "$max3" "$bad3") | the reference |"
  echo
  echo "Speed: the $backend columns' fps are medians of $rounds round(s), the four alternating"
  echo "within each round (load average $load3);"
  echo "their ratios to the ray tracer are the medians of the per-round ratios (rounds' range:"
  echo "classic $(range "${env_r[@]}"), reflection only $(range "${none_r[@]}"), inter-reflection"
  echo "$(range "${inter_r[@]}")). The CPU reference: one run."
  echo
  echo "Classic environment mapping: rasterized primary hits (the paper's classic method is the"
  echo "GPU's rasterizer with a cube map; the ray tracer column traces its primaries), exact"
  echo "shadow feelers (\`--primary raster --reflections envmap\`), one cube map captured at"
  echo "set_scene from the scene's centre, read by the reflected rays. The reflection-only"
  echo "column is the same without shadows (\`--shadows none\`: every light counts as visible,"
  echo "no feelers, the cube map captured unshadowed too): the effects the paper's Table 3"
  echo "gives its classic column, and the one its 101.74 fps stands beside."
  echo "Inter-reflection: a cube map per mirror object (4), captured every frame from its"
  echo "bounding-sphere centre, $bounces3 bounces; rays leaving an object read its own map."
  echo "Error: each column's first frame against the CPU double reference tracer's image at the"
  echo "ray tracer's settings (traced primaries and reflections, exact feelers; what correct"
  echo "is), compared as Table 2 and \`raystream-bench --times --error\` compare: linear RGB,"
  echo "PSNR with peak 1, the largest channel difference, and the share of pixels with a"
  echo "channel off by more than 8/255. The environment maps' error is their approximation"
  echo "(no self-reflection, parallax, missing shadows); the ray tracer's is fp32 against double."
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
