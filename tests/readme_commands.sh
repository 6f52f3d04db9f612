#!/usr/bin/env bash
# The README cannot drift: every command in README.md's ```sh blocks is run, in order, in
# one working folder, as written except for the substitutions below; each must exit 0 and
# every output it names must exist and be non-empty.
#   readme_commands.sh SOURCE_DIR BUILD_DIR WORK_DIR
#
# What the test changes, and why (nothing else is changed):
#   - `build/` (and `--build build`) is the build under test, `tools/` the source tree's.
#   - Small sizes and short runs, so the suite stays quick (the commands themselves are
#     the README's): raystream-render --size 64x64; raystream-bench Table 1 and 2 on the
#     box at 32 pixels, one repeat (one frame for --times); raystream-report --quick; paper-tables.sh
#     --quick; raystream-optsynth -n 12; raystream-streambench --size 64x64, 4 frames,
#     one quality.
#   - raystream-calib reads checkerboard pairs a user took: the test first writes
#     synthetic ones into the working folder (raystream-calib --synth . --views 6).
#   - raystream-server runs in the background on a free port (--port 0 --port-file)
#     until the viewer line has run, then gets SIGTERM and must exit 0; the viewer runs
#     for 3 s against that port (--duration 3), headless when there is no $DISPLAY.
# Not run, each for its reason:
#   - tools/render-demo.sh: installs packages and reconfigures the build folder (Release,
#     tests off) it would be run from; it is CI's main job.
#   - tools/test-all.sh: runs this suite, so it would run itself.
#   - `cc app.c $(pkg-config ...)`: tests/install.cmake builds an outside project against
#     an installed tree, both ways.
set -u
src=$1
build=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1
passed=0 failed=0 ran=0
ok() { passed=$((passed + 1)); echo "ok: $1"; }
bad() { failed=$((failed + 1)); echo "FAILED: $1"; }

# Commands of the ```sh blocks, one per line, continuation lines joined.
commands=$(awk '
  /^```sh$/ { inside = 1; cmd = ""; next }
  /^```/ { inside = 0; next }
  inside && NF {
    line = $0
    if (sub(/\\$/, "", line)) { cmd = cmd line; next }
    print cmd line; cmd = ""
  }' "$src/README.md")
[ -n "$commands" ] || { echo "FAILED: no commands found in $src/README.md"; exit 1; }

excluded() {
  case $1 in
    *tools/render-demo.sh*) echo "installs packages and reconfigures the build it runs from" ;;
    *tools/test-all.sh*) echo "runs this suite: it would run itself" ;;
    *'$(pkg-config'*) echo "tests/install.cmake builds against an installed tree" ;;
    *) return 1 ;;
  esac
}

server_pid=""
port=""
n=0
while IFS= read -r cmd; do
  n=$((n + 1))
  if why=$(excluded "$cmd"); then
    echo "skip: $cmd  ($why)"
    continue
  fi
  # Split as the shell would (quotes, trailing comments).
  eval "set -- $cmd"
  words=()
  prev=""
  for w in "$@"; do
    case $w in
      build/*) w=$build/${w#build/} ;;
      tools/*) [ -e "$src/$w" ] && w=$src/$w ;;
      build) [ "$prev" = --build ] && w=$build ;;
    esac
    words+=("$w")
    prev=$w
  done
  prog=${words[0]}
  [ "$prog" = bash ] && prog=${words[1]}
  prog=$(basename "$prog")
  # outputs: the value after an output option; optsynth's folder
  outputs=()
  for ((i = 0; i < ${#words[@]}; i++)); do
    case ${words[i]} in
      --out | --stats | --depth | --out-obj | --out-view | -o | --json)
        [ "$prog" = raystream-viewer ] || outputs+=("${words[i + 1]}") ;;
    esac
  done
  case $prog in
    raystream-render)
      for ((i = 0; i < ${#words[@]}; i++)); do
        [ "${words[i]}" = --size ] && words[i + 1]=64x64
      done ;;
    raystream-bench)
      if [[ " ${words[*]} " == *" --table 2 "* ]]; then
        words+=(--scene box --size 32 --repeats 1)
      elif [[ " ${words[*]} " == *" --times "* ]]; then
        words+=(--size 32 --repeats 1)
      else
        words+=(--scene box --size 32 --flat-size 16 --repeats 1)
      fi ;;
    raystream-report) words+=(--quick) ;;
    paper-tables.sh) words+=(--quick) ;;
    raystream-optsynth)
      words+=(-n 12)
      outputs+=("${words[1]}") ;;
    raystream-streambench) words+=(--size 64x64 --frames 4 --qualities 80) ;;
    raystream-calib)
      "$build/tools/calib/raystream-calib" --synth . --views 6 >/dev/null 2>&1 ||
        bad "calib: could not write synthetic checkerboard pairs" ;;
    raystream-server)
      words+=(--port 0 --port-file "$work/port.json")
      rm -f port.json
      "${words[@]}" >"server.out" 2>"server.err" &
      server_pid=$!
      for _ in $(seq 600); do [ -s port.json ] && break; sleep 0.1; done
      port=$(sed -n 's/.*"port":[[:space:]]*\([0-9]*\).*/\1/p' port.json 2>/dev/null)
      ran=$((ran + 1))
      if [ -n "$port" ]; then ok "started: $cmd (port $port)"
      else bad "server did not start: $(head -c 300 server.err)"; fi
      continue ;;
    raystream-viewer)
      for ((i = 0; i < ${#words[@]}; i++)); do
        [ "${words[i]}" = --server ] && words[i + 1]=127.0.0.1:${port:-1}
      done
      words+=(--duration 3)
      if [ -z "${DISPLAY:-}" ]; then
        words+=(--headless --stats "$work/viewer.json")
        outputs+=("$work/viewer.json")
      fi ;;
  esac
  ran=$((ran + 1))
  timeout 600 "${words[@]}" >"cmd$n.out" 2>"cmd$n.err"
  rc=$?
  if [ "$rc" -ne 0 ]; then
    bad "exit $rc: $cmd -- $(tail -c 400 "cmd$n.err")"
  else
    missing=""
    for f in "${outputs[@]}"; do
      if [ -d "$f" ]; then [ -n "$(ls -A "$f")" ] || missing+=" $f(empty)"
      else [ -s "$f" ] || missing+=" $f"; fi
    done
    if [ -n "$missing" ]; then bad "$cmd: outputs missing:$missing"
    else ok "$cmd${outputs[*]:+ -> ${outputs[*]}}"; fi
  fi
  if [ "$prog" = raystream-viewer ] && [ -n "$server_pid" ]; then
    kill -TERM "$server_pid" 2>/dev/null
    wait "$server_pid"
    rc=$?
    server_pid=""
    [ "$rc" -eq 0 ] && ok "server ended cleanly" || bad "server exit $rc: $(tail -c 300 server.err)"
  fi
done <<<"$commands"
[ -z "$server_pid" ] || { kill -TERM "$server_pid"; wait "$server_pid"; bad "server line without a viewer line"; }
[ "$ran" -ge 10 ] || bad "only $ran README commands ran"
echo "$passed passed, $failed failed ($ran README commands run)"
[ "$failed" -eq 0 ]
