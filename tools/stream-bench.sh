#!/usr/bin/env bash
# The whole remote rendering chain, measured: sim tracker -> pose -> raystream-viewer ->
# raystream-server (render, JPEG) -> emulated link -> viewer (decode, show), at 512x512 and
# 256x256. Prints per size: the server's own render rate, frames rendered and received,
# delivered fps and motion-to-photon latency (median, p99). Not a test.
#   tools/stream-bench.sh [BUILD_DIR=build] [SECONDS=10] [SCENE=box] [SERVER_ARGS...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
secs=${2:-10}
scene=${3:-box}
shift $(( $# < 3 ? $# : 3 ))
server=$build/apps/server/raystream-server
viewer=$build/apps/viewer/raystream-viewer
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
jget() { sed -n "s/^[[:space:]]*\"$2\":[[:space:]]*\([-0-9.e+]*\),\{0,1\}$/\1/p" "$1" | head -n1; }
echo "machine: $(nproc) cores, $(uptime | sed 's/.*load/load/')"
printf '%-8s %12s %9s %9s %9s %10s %10s %7s\n' size render_fps rendered received view_fps \
  lat_med_ms lat_p99_ms gaps
for size in 512x512 256x256; do
  "$server" --port 0 --port-file "$work/port.json" --scene "$scene" --size "$size" \
    --link-mbps 25 --link-latency-ms 5 --encoding jpeg444 --quality 90 \
    --duration $((secs + 4)) --stats "$work/s.json" "$@" 2> "$work/server.log" &
  spid=$!
  for _ in $(seq 100); do [ -s "$work/port.json" ] && break; sleep 0.1; done
  port=$(jget "$work/port.json" port)
  "$viewer" --server 127.0.0.1:"$port" --scene "$scene" --size "$size" --headless \
    --duration "$secs" --stats "$work/v.json" --tracker "sim:realtime=1" > /dev/null
  wait $spid
  rm -f "$work/port.json"
  ms=$(jget "$work/s.json" render_ms_mean)
  printf '%-8s %12.2f %9d %9d %9.2f %10.1f %10.1f %7d\n' "$size" \
    "$(awk "BEGIN { print 1000 / $ms }")" "$(jget "$work/s.json" frames_rendered)" \
    "$(jget "$work/v.json" frames)" "$(jget "$work/v.json" fps)" \
    "$(jget "$work/v.json" latency_median_ms)" "$(jget "$work/v.json" latency_p99_ms)" \
    "$(jget "$work/v.json" frame_id_gaps)"
done
