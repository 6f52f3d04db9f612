#!/usr/bin/env bash
# The apps' command lines (rs_cli, like every tool): --help on stdout with exit 0, a bad
# value named with its valid range (exit 2), every output target checked at start (exit 1
# before any work), and an output that cannot be written at shutdown fails the run.
#   apps_cli.sh SERVER WORK_DIR VIEWER
source "$(dirname "$0")/cli_harness.sh"
server=$bin
viewer=$3

# help PROGRAM WORDS...: --help exits 0, prints on stdout only, and names every WORD
help() {
  local prog=$1
  shift
  "$prog" --help >help.txt 2>help.err
  local rc=$?
  if [ "$rc" -ne 0 ] || [ -s help.err ]; then bad "$(basename "$prog") --help: exit $rc, stderr '$(cat help.err)'"; return; fi
  for w in "$@"; do
    grep -q -- "$w" help.txt || { bad "$(basename "$prog") --help does not name $w"; return; }
  done
  ok "$(basename "$prog") --help on stdout, exit 0, names $*"
}

help "$server" --port-file --stats --encoding --backend --passes --shadows 7878
help "$viewer" --eye-frame --last --linger --out --stats --backend --render-scale

bin=$server
fails_cleanly "server --passes 0" 2 "^raystream-server: --passes: '0' .*1\.\.64" --passes 0 && ok "server --passes 0 named"
fails_cleanly "server --port 70000" 2 "--port: '70000' .*0\.\.65535" --port 70000 && ok "server --port named"
fails_cleanly "server --quality 0" 2 "--quality: '0' .*1\.\.100" --quality 0 && ok "server --quality named"
fails_cleanly "server --encoding" 2 "--encoding: 'png' is not jpeg, jpeg444 or raw" --encoding png && ok "server --encoding named"
fails_cleanly "server --size" 2 "--size: '0x5' .*1\.\.4096" --size 0x5 && ok "server --size named"
fails_cleanly "server --lights" 2 "--lights: '65' .*1\.\.64" --lights 65 && ok "server --lights named"
fails_cleanly "server --link-mbps" 2 "--link-mbps: '-1'" --link-mbps -1 && ok "server --link-mbps named"
fails_cleanly "server --port needs a value" 2 "option --port needs a value" --port && ok "server missing value named"
# Output targets: refused at start, before listening (a 20 s run that ends in the error,
# or exits 0 after it, fails here).
for opt in --stats --port-file; do
  fails_cleanly "server $opt /nonexist" 1 "/nonexist/x.json" --port 0 --duration 20 "$opt" /nonexist/x.json &&
    ok "server $opt /nonexist refused at start"
done
# A stats file that cannot be written at shutdown: its folder removed during the run.
mkdir -p gone
timeout 60 "$server" --port 0 --port-file port.json --duration 1 --stats gone/s.json \
  >/dev/null 2>late.err &
spid=$!
for _ in $(seq 100); do [ -s port.json ] && break; sleep 0.1; done
rm -rf gone
wait "$spid"
rc=$?
if [ "$rc" -ne 0 ] && [ "$rc" -ne 124 ] && grep -q "gone/s.json" late.err; then
  ok "server stats unwritable at shutdown: exit $rc"
else
  bad "server stats unwritable at shutdown: exit $rc, stderr $(tail -n 2 late.err)"
fi

bin=$viewer
fails_cleanly "viewer --fov 200" 2 "^raystream-viewer: --fov: '200' .*\(0, 180\)" --fov 200 && ok "viewer --fov named"
fails_cleanly "viewer --view" 2 "--view: 'side' is not camera or window" --view side && ok "viewer --view named"
fails_cleanly "viewer --render-scale" 2 "--render-scale: '0.3'" --render-scale 0.3 && ok "viewer --render-scale named"
fails_cleanly "viewer --frames 0" 2 "--frames: '0' .*1\.\.100000000" --frames 0 && ok "viewer --frames named"
fails_cleanly "viewer --passes 99" 2 "--passes: '99' .*1\.\.64" --passes 99 && ok "viewer --passes named"
fails_cleanly "viewer --bogus" 2 "unknown option '--bogus'" --bogus && ok "viewer unknown option named"
for opt in --stats --last; do
  fails_cleanly "viewer $opt /nonexist" 1 "/nonexist/x" --headless --duration 20 \
    --backend cpu "$opt" /nonexist/x && ok "viewer $opt /nonexist refused at start"
done
touch afile
fails_cleanly "viewer --out FILE" 1 "afile: exists and is not a folder" --headless --frames 1 \
  --out afile/frames && ok "viewer --out under a file refused at start"
# --out DIR is created, like every tool's.
if timeout 120 "$viewer" --headless --frames 1 --size 16x16 --backend cpu --out new/frames \
  >out.txt 2>out.err && [ -n "$(ls new/frames)" ]; then
  ok "viewer --out new/frames created and written"
else
  bad "viewer --out new/frames: $(cat out.err)"
fi
finish
