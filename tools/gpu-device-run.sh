#!/usr/bin/env bash
# The GPU run in one command, on a machine with none of the project's packages (the device
# tool's lent NVIDIA machine), from the repository root: unpacks tools/gpu-bundle.sh's
# archive, points the loader at its libraries and, where /usr/local/nvidia has one, at the
# NVIDIA EGL driver, then runs tools/gpu-bench.sh (Tables 1-3, its report), issue 20's
# target line (Table 2 on Cow17 with 4 lights) and the same frame's times with fragment and
# compute kernels alternately (a Hopper data-centre GPU shades fragments on 2 of its 66 TPCs:
# docs/gles.md "Compute kernels"). Everything lands in the output folder: the report,
# gpu-run.log (nvidia-smi, the bundle's manifest, every command and its output) and the JSON
# of the target line and of the times. Exits non-zero, naming the step, when any step fails.
set -euo pipefail
usage() {
  cat <<'EOF'
usage: tools/gpu-device-run.sh [--quick] [--bundle FILE] [--out DIR] [--platform NAME]
  Unpacks the bundle and runs tools/gpu-bench.sh, Table 2 on Cow17 with 4 lights and that
  frame's times with fragment and compute kernels (3 alternating rounds) on the egl
  backend, writing the report, gpu-run.log, table2-cow17-4lights.json and
  times-cow17-4lights.json into DIR.
  --quick          tiny sizes, one frame: the plumbing only (no figures)
  --bundle FILE    tools/gpu-bundle.sh's archive (default: .gpu/raystream-gpu.tar.gz)
  --out DIR        where the results go (default: $OUT where set, else docs/report)
  --platform NAME  EGL platform for tools/gpu-bench.sh: device (default), gbm,
                   surfaceless or auto
EOF
}
die() { echo "gpu-device-run: $*" >&2; exit "${code:-1}"; }
root=$(cd "$(dirname "$0")/.." && pwd)
bundle=$root/.gpu/raystream-gpu.tar.gz
out=${OUT:-$root/docs/report}
platform=device
quick=()
while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --quick) quick=(--quick); shift ;;
    --bundle|--out|--platform)
      [ $# -ge 2 ] && [ -n "$2" ] || code=2 die "$1 needs a value (try --help)"
      case $1 in --bundle) bundle=$2 ;; --out) out=$2 ;; --platform) platform=$2 ;; esac
      shift 2 ;;
    *) code=2 die "unknown option '$1' (try --help)" ;;
  esac
done
[ -f "$bundle" ] || die "no bundle at $bundle (make it with tools/gpu-bundle.sh)"
[ -d "$out" ] && [ -w "$out" ] || die "cannot write to $out (a writable folder is needed)"

tmp=""
trap 'rm -rf "$tmp"' EXIT
tmp=$(mktemp -d)
tar -C "$tmp" -xzf "$bundle" || die "cannot unpack $bundle"
bench=$tmp/build/tools/bench/raystream-bench
[ -x "$bench" ] && [ -x "$tmp/bin/jq" ] && [ -f "$tmp/MANIFEST" ] ||
  die "$bundle is not a tools/gpu-bundle.sh archive"

export LD_LIBRARY_PATH=$tmp/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export PATH=$tmp/bin:$PATH
export RS_DATA_DIR=${RS_DATA_DIR:-$root/data}
nvidia=/usr/local/nvidia
if [ -f "$nvidia/share/glvnd/egl_vendor.d/10_nvidia.json" ]; then
  export __EGL_VENDOR_LIBRARY_FILENAMES=$nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  for d in "$nvidia/lib64" "$nvidia/lib"; do
    [ -d "$d" ] && LD_LIBRARY_PATH=$LD_LIBRARY_PATH:$d
  done
fi

log=$out/gpu-run.log
: >"$log" || die "cannot write $log"
# step NAME CMD...: the command and its output into the log (its stdout into $stdout where
# that is set); a failure stops the run with one line, the log's last line in it
step() {
  local name=$1
  shift
  echo "\$ $*" >>"$log"
  "$@" >>"${stdout:-$log}" 2>>"$log" ||
    die "$name failed: $(tail -n 1 "$log") (the whole output: $log)"
}
{
  echo "# tools/gpu-device-run.sh ${quick[*]} --platform $platform, $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "# machine: $(uname -srm), $(nproc) cores; $(. /etc/os-release 2>/dev/null && echo "$PRETTY_NAME")"
  sed 's/^/# bundle /' "$tmp/MANIFEST"
  echo "# nvidia-smi: $(nvidia-smi -L 2>/dev/null || echo none)"
  echo "# LD_LIBRARY_PATH=$LD_LIBRARY_PATH"
  echo "# __EGL_VENDOR_LIBRARY_FILENAMES=${__EGL_VENDOR_LIBRARY_FILENAMES:-}"
} >>"$log"
step "the bundle's raystream-bench (does this machine's glibc run it?)" "$bench" --help
echo "gpu-device-run: Tables 1-3 (tools/gpu-bench.sh ${quick[*]} --platform $platform)" >&2
stdout=$tmp/report.txt step "tools/gpu-bench.sh" bash "$root/tools/gpu-bench.sh" "${quick[@]}" \
  --build "$tmp/build" --platform "$platform" --out-dir "$out"
report=$(tail -n 1 "$tmp/report.txt")
[ -n "$report" ] && [ -s "$report" ] || die "tools/gpu-bench.sh named no report (see $log)"
echo "report: $report" >>"$log"

# Issue 20's GPU target: Cow17, 2 passes, 4 lights, 512x512 (--quick: 64x64, one frame).
target=(--table 2 --backend egl --scene cow17 --lights 4)
if [ ${#quick[@]} -gt 0 ]; then target+=(--size 64 --repeats 1); else target+=(--repeats 9); fi
[ "$platform" = auto ] || export RS_EGL_PLATFORM=$platform
echo "gpu-device-run: raystream-bench ${target[*]}" >&2
# the JSON lands in $out only whole and with rows
step "Table 2 on Cow17 with 4 lights" "$bench" "${target[@]}" --json "$tmp/target.json"
jq -e '.rows | length > 0' "$tmp/target.json" >/dev/null ||
  die "Table 2 on Cow17 wrote no rows (see $log)"
cp "$tmp/target.json" "$out/table2-cow17-4lights.json" || die "cannot write $out"

# The same frame's times as fragment passes and as compute dispatches, alternating round by
# round (--quick: 64x64, one frame, one round); the rows of every run in one JSON.
times=(--times --backend egl --passes 2 --lights 4)
rounds=3
if [ ${#quick[@]} -gt 0 ]; then times+=(--size 64 --repeats 1); rounds=1; else times+=(--size 512 --repeats 9); fi
for r in $(seq 1 "$rounds"); do
  for k in fragment compute; do
    echo "gpu-device-run: raystream-bench ${times[*]} --kernels $k cow17 (round $r of $rounds)" >&2
    step "Cow17 times with $k kernels" "$bench" "${times[@]}" --kernels "$k" \
      --json "$tmp/times-$r-$k.json" cow17
  done
done
jq -s '{mode: "times", rows: [.[].rows[]]}' "$tmp"/times-*.json >"$tmp/times.json" &&
  jq -e "[.rows[].kernels] | (index(\"fragment\") != null) and (index(\"compute\") != null)" \
    "$tmp/times.json" >/dev/null || die "the Cow17 times wrote no rows of both kernels (see $log)"
cp "$tmp/times.json" "$out/times-cow17-4lights.json" || die "cannot write $out"
echo "$report"
echo "$log"
