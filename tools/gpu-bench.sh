#!/usr/bin/env bash
# The paper's tables on a GPU: tools/paper-tables.sh (Tables 1-3, raystream-bench --json read
# with jq) run on the egl backend through one EGL platform (default "device": an NVIDIA GPU
# with no display or X server), wrapped in a report that names the machine, the GPU, the
# renderer string, the commands and the load before and after, written all or nothing to
# docs/report/paper-tables-<renderer>.md (the renderer string in lower case, every run of
# other characters a '-'). It runs the same way on llvmpipe (tests/gpu_bench_smoke.sh).
set -euo pipefail
usage() {
  cat <<'EOF'
usage: tools/gpu-bench.sh [--quick] [--build DIR] [--platform NAME] [--out-dir DIR]
  Tables 1-3 (tools/paper-tables.sh) on the egl backend through one EGL platform, written to
  DIR/paper-tables-<renderer>.md (all or nothing); the file's name on stdout, progress on
  stderr.
  --quick          tiny sizes, one frame (tools/paper-tables.sh --quick): the plumbing
  --build DIR      the build folder (default: $RS_BUILD_DIR, else build/ in the source tree;
                   a Release build for figures)
  --platform NAME  EGL platform: device (default; NVIDIA without a display), gbm,
                   surfaceless, or auto (the first that works)
  --out-dir DIR    the report's folder (default: docs/report in the source tree)
EOF
}
die() { echo "gpu-bench: $*" >&2; exit "${code:-1}"; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RS_BUILD_DIR:-$root/build}
platform=device
outdir=$root/docs/report
quick=()
while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --quick) quick=(--quick); shift ;;
    --build|--platform|--out-dir)
      [ $# -ge 2 ] && [ -n "$2" ] || code=2 die "$1 needs a value (try --help)"
      case $1 in --build) build=$2 ;; --platform) platform=$2 ;; --out-dir) outdir=$2 ;; esac
      shift 2 ;;
    *) code=2 die "unknown option '$1' (try --help)" ;;
  esac
done
case $platform in
  device|gbm|surfaceless) export RS_EGL_PLATFORM=$platform ;;
  auto) unset RS_EGL_PLATFORM ;;
  *) code=2 die "--platform $platform: not device, gbm, surfaceless or auto" ;;
esac
[ -d "$outdir" ] && [ -w "$outdir" ] || die "cannot write to $outdir (a writable folder is needed)"
bench=$build/tools/bench/raystream-bench
[ -x "$bench" ] || die "$bench not built (cmake --build $build)"
command -v jq >/dev/null || die "jq is needed to read raystream-bench --json (tools/deps.sh)"

tmp="" outtmp=""
trap 'rm -rf "$tmp"; [ -z "$outtmp" ] || rm -f "$outtmp"' EXIT
tmp=$(mktemp -d)
# The renderer string names the file: one tiny frame on the backend and platform measured.
"$bench" --times --backend egl --size 8 --repeats 1 --json "$tmp/probe.json" box \
  >"$tmp/probe.txt" 2>"$tmp/probe.err" ||
  die "no egl context on platform $platform: $(tail -n 1 "$tmp/probe.err")"
renderer=$(jq -r '.rows[0].renderer' "$tmp/probe.json") || die "cannot read the renderer string"
[ -n "$renderer" ] && [ "$renderer" != null ] || die "raystream-bench named no renderer"
# The GL_RENDERER part only: raystream-bench appends " (<GL version>; EGL <platform>)".
name=$(printf '%s' "${renderer% (OpenGL*}" | tr '[:upper:]' '[:lower:]' | sed -E 's/[^a-z0-9.]+/-/g; s/^-+//; s/-+$//' | cut -c1-80)
out=$outdir/paper-tables-$name.md
outtmp=$(mktemp "$out.tmp-XXXXXX") || die "cannot write $out"
load0=$(cut -d' ' -f1-3 /proc/loadavg)
tables=(bash "$root/tools/paper-tables.sh" "${quick[@]}" --build "$build" --backend egl)
echo "gpu-bench: ${tables[*]} (RS_EGL_PLATFORM=${RS_EGL_PLATFORM:-auto})" >&2
"${tables[@]}" >"$tmp/tables.md" || die "tools/paper-tables.sh failed; $out not written"
load1=$(cut -d' ' -f1-3 /proc/loadavg)
gpus=$(nvidia-smi -L 2>/dev/null || true)
{
  echo "# The paper's tables on $renderer"
  echo
  echo "- Machine: $(uname -srm), $(nproc) cores, $(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -1)"
  echo "- GPU: ${gpus:-none listed by nvidia-smi}"
  echo "- Renderer string (GL_RENDERER): $renderer; EGL platform: $platform"
  echo "- Commands: \`RS_EGL_PLATFORM=${RS_EGL_PLATFORM:-} tools/gpu-bench.sh ${quick[*]} --platform $platform\`,"
  echo "  which runs \`tools/paper-tables.sh ${quick[*]} --backend egl\` with the build in $build"
  echo "- Load average (1, 5, 15 min): $load0 before, $load1 after"
  echo "- Date: $(date -u '+%Y-%m-%d %H:%M UTC'); source: $(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)"
  echo
  sed '1{/^# /d}' "$tmp/tables.md"
} >"$outtmp" || die "cannot write $out"
[ -s "$outtmp" ] || die "empty report; $out not written"
mv -f "$outtmp" "$out" || die "cannot write $out"
outtmp=""
echo "$out"
echo "gpu-bench: wrote $out" >&2
