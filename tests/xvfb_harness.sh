# Sourced by the window tests after cli_harness.sh: skips (exit 77) without Xvfb or xwd,
# starts Xvfb on a free display (the first at or above $1, default 90) and exports
# DISPLAY; background processes added to `pids` are killed on exit.
if ! command -v Xvfb >/dev/null || ! command -v xwd >/dev/null; then
  echo "skipped: Xvfb or xwd not installed (tools/deps.sh installs them)"
  exit 77
fi
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; wait 2>/dev/null; }
trap cleanup EXIT
# a free display number: no lock file and no socket
d=${1:-90}
while [ -e /tmp/.X$d-lock ] || [ -e /tmp/.X11-unix/X$d ]; do d=$((d + 1)); done
Xvfb :$d -screen 0 320x240x24 -nolisten tcp > xvfb.log 2>&1 &
pids+=($!)
for _ in $(seq 100); do [ -e /tmp/.X11-unix/X$d ] && break; sleep 0.1; done
[ -e /tmp/.X11-unix/X$d ] && ok "Xvfb on :$d" || { bad "Xvfb did not start: $(cat xvfb.log)"; finish; exit 1; }
export DISPLAY=:$d
