#!/usr/bin/env bash
# raystream-track end to end (registered by track_cli.cmake): track_cli.sh TOOL WORKDIR
set -euo pipefail
tool=$1
work=$2
mkdir -p "$work"
# On failure, show what the tool said: a flaky check under load must be diagnosable.
fail() {
  echo "track_cli: $*" >&2
  for f in "$work"/*.err "$work"/err.txt; do
    [ -s "$f" ] && { echo "--- $f" >&2; tail -n 5 "$f" >&2; }
  done
  exit 1
}
# A failed check must not leave a device process (they run up to 120 s) holding ctest's pipe.
trap 'jobs -p | xargs -r kill 2> /dev/null || true' EXIT

# 1. A simulated run prints one pose line per sample and the final counters.
out=$("$tool" -n 200 --stats 0 'sim:seed=1&noise=0.5mm')
[ "$(grep -c ' seq=' <<<"$out")" -eq 200 ] || fail "expected 200 pose lines"
grep -q '^# stats samples=200 frames=200 garbage_bytes=0 crc=0' <<<"$out" || fail "stats line"
grep -q 'RS_POSE_OK' <<<"$out" || fail "no solved pose"
! grep -qi 'nan' <<<"$out" || fail "NaN in output"

# 1b. The README's line, as written: a simulator that is not real-time runs one pass of
#     its script (6 s of motion at 120 Hz) and stops, instead of flooding stdout forever.
timeout 60 "$tool" sim:seed=1 > "$work/readme.txt" 2> "$work/readme.err" \
  || fail "sim:seed=1 did not end by itself with exit 0"
[ "$(grep -c ' seq=' "$work/readme.txt")" -eq 720 ] || fail "sim:seed=1: want 720 pose lines"
grep -q '^# stats samples=720 ' "$work/readme.txt" || fail "sim:seed=1: final counters"
#     duration=, -n and --duration still say how long; a custom script sets the pass.
[ "$(timeout 60 "$tool" --stats 0 'sim:duration=2s' | grep -c ' seq=')" -eq 240 ] \
  || fail "sim:duration=2s: want 240 samples"
[ "$(timeout 60 "$tool" --stats 0 'sim:script=still:1,walk:0.5' | grep -c ' seq=')" -eq 180 ] \
  || fail "sim:script=still:1,walk:0.5: want one pass, 180 samples"

# 2. Record, then replay: the same samples come back (identical pose lines).
"$tool" -q -n 300 --stats 0 -r "$work/run.rec" 'sim:seed=2&noise=1mm&swap=0.05&dropout=0.05' \
  > "$work/rec.txt"
"$tool" -n 300 --stats 0 'sim:seed=2&noise=1mm&swap=0.05&dropout=0.05' > "$work/live.txt"
"$tool" --stats 0 "replay:$work/run.rec" > "$work/replay.txt"
grep -q '^# stats samples=300 frames=300' "$work/replay.txt" || fail "replay count"
diff <(grep ' seq=' "$work/live.txt") <(grep ' seq=' "$work/replay.txt") > /dev/null \
  || fail "replayed poses differ from the live run"

# 2b. A closed output pipe ends the run cleanly: the recording is complete and in place
#     (the recorder renames its temporary file only when finished).
"$tool" -r "$work/pipe.rec" 'sim:rate=1000' | head -n 3 > /dev/null \
  || fail "closed pipe: non-zero exit"
ls "$work"/pipe.rec.tmp-* > /dev/null 2>&1 && fail "closed pipe left a temporary file"
grep -q '^# stats samples=[1-9]' <("$tool" --stats 0 "replay:$work/pipe.rec") \
  || fail "closed pipe: recording unreadable"

# 3. --duration stops a realtime source on time: 0.3 s at 100 Hz is about 30 samples
#    (counted, not timed: the process's own start-up under load is no part of it).
timeout 60 "$tool" -q -d 0.3 --stats 0 'sim:realtime=1&rate=100' > "$work/dur.txt" \
  || fail "--duration 0.3 did not end"
n=$(sed -n 's/^# stats samples=\([0-9]*\) .*/\1/p' "$work/dur.txt")
[ -n "$n" ] && [ "$n" -ge 1 ] && [ "$n" -le 40 ] || fail "--duration 0.3 at 100 Hz: ${n:-no} samples"

# 4. --pty plays a simulated device into a pseudo-terminal; a second process reads it
#    through the serial path (tty raw mode, poll, parser) and solves poses. The device
#    runs until the reader is done (killed then): a fixed duration raced a sanitized
#    reader's start-up on a loaded machine ("cannot open /dev/pts/0").
rm -f "$work/pty.txt"
"$tool" --pty -d 120 'sim:realtime=1&rate=200&seed=3' > "$work/pty.txt" &
server=$!
for _ in $(seq 300); do [ -s "$work/pty.txt" ] && break; sleep 0.1; done
pty=$(head -n 1 "$work/pty.txt")
[ -n "$pty" ] || fail "--pty printed no path"
"$tool" -n 100 --stats 0 "serial:$pty" > "$work/serial.txt"
kill "$server" 2> /dev/null || true
wait "$server" 2> /dev/null || true
[ "$(grep -c 'RS_POSE_OK' "$work/serial.txt")" -ge 99 ] || fail "serial poses"
grep -q '^# stats samples=100 frames=100' "$work/serial.txt" || fail "serial stats"

# 4b. --pty with nobody reading fills the line; SIGINT must still end it (within a hang
#     timeout of 60 s: how soon is not asserted). The signal goes only once the tool has
#     printed its path, so its handler is in place: a background job of this script starts
#     with SIGINT ignored, and a loaded machine can take seconds to get that far.
rm -f "$work/pty_idle.txt"
"$tool" --pty 'sim:realtime=1&rate=5000' > "$work/pty_idle.txt" &
server=$!
for _ in $(seq 300); do [ -s "$work/pty_idle.txt" ] && break; sleep 0.1; done
sleep 1.5
kill -INT "$server"
for _ in $(seq 600); do kill -0 "$server" 2> /dev/null || break; sleep 0.1; done
if kill -0 "$server" 2> /dev/null; then
  kill -KILL "$server"
  fail "--pty with no reader ignored SIGINT (still running 60 s later)"
fi
wait "$server" || fail "--pty interrupted exited non-zero"

# 4c. --reconnect: the device (a pty behind a symlink, removed before the hang-up so no
#     other pty can be opened by mistake) goes away; the tool reports it, keeps trying,
#     and --duration still ends the run cleanly.
#     The waits are generous: under a loaded CI machine a sanitized binary can take
#     seconds to start, and a device that ends before its reader opened it proves nothing.
rm -f "$work/pty_rc.txt"
"$tool" --pty -d 120 'sim:realtime=1&rate=200&seed=4' > "$work/pty_rc.txt" &
server=$!
for _ in $(seq 300); do [ -s "$work/pty_rc.txt" ] && break; sleep 0.1; done
[ -s "$work/pty_rc.txt" ] || fail "--pty (reconnect case) printed no path within 30 s"
ln -sf "$(head -n 1 "$work/pty_rc.txt")" "$work/tty"
rm -f "$work/rc.txt"
"$tool" -q --stats 0.2 --reconnect -d 9 "serial:$work/tty" > "$work/rc.txt" 2> "$work/rc.err" &
client=$!
# Remove the link once the client reads through it (it holds the open line), then take
# the device away (SIGINT), however long a loaded machine took to start the client.
for _ in $(seq 300); do grep -qs 'samples=[1-9]' "$work/rc.txt" && break; sleep 0.1; done
grep -q 'samples=[1-9]' "$work/rc.txt" || fail "--reconnect client read no sample within 30 s"
rm -f "$work/tty"
kill -INT "$server"
wait "$server" || fail "--pty server failed"
for _ in $(seq 600); do kill -0 "$client" 2> /dev/null || break; sleep 0.1; done
if kill -0 "$client" 2> /dev/null; then
  kill -KILL "$client"
  fail "--reconnect ignored --duration while the device was away (running 60 s later)"
fi
wait "$client" || fail "--reconnect run exited non-zero"
grep -q 'reconnecting' "$work/rc.err" || fail "no reconnect message"
tail -n 1 "$work/rc.txt" | grep -q 'disconnects=1 ' || fail "disconnect not counted"

# 4d. A disconnect without --reconnect ends the run with one error line, exit 1, and
#     still the final counters. The device goes away (SIGINT) only once the reader has
#     samples, however long a loaded machine took to start it.
rm -f "$work/pty_dc.txt"
"$tool" --pty -d 60 'sim:realtime=1&rate=200&seed=5' > "$work/pty_dc.txt" &
server=$!
for _ in $(seq 300); do [ -s "$work/pty_dc.txt" ] && break; sleep 0.1; done
rm -f "$work/dc.txt"
"$tool" -q --stats 0.2 "serial:$(head -n 1 "$work/pty_dc.txt")" > "$work/dc.txt" 2> "$work/dc.err" &
client=$!
for _ in $(seq 300); do grep -qs 'samples=[1-9]' "$work/dc.txt" && break; sleep 0.1; done
grep -q 'samples=[1-9]' "$work/dc.txt" || fail "disconnect: the client read no sample within 30 s"
kill -INT "$server"
wait "$server" || fail "--pty server failed"
rc=0
wait "$client" || rc=$?
[ "$rc" -eq 1 ] || fail "disconnect exited $rc, want 1"
[ "$(wc -l < "$work/dc.err")" -eq 1 ] || fail "disconnect: not one error line"
tail -n 1 "$work/dc.txt" | grep -q '^# stats samples=[1-9].* disconnects=1 ' \
  || fail "disconnect: no final stats line"

# 4e. Output that cannot be written (a full device, a closed stdout) is an error, never a
#     silent exit 0.
set +e
"$tool" -n 50 --stats 0 'sim:seed=1' > /dev/full 2> "$work/full.err"
rc_full=$?
"$tool" -q -n 50 --stats 0 'sim:seed=1' > /dev/full 2> "$work/fullq.err"
rc_fullq=$?
"$tool" -n 5 'sim:seed=1' >&- 2> "$work/closed.err"
rc_closed=$?
set -e
[ "$rc_full" -eq 1 ] && [ "$rc_fullq" -eq 1 ] && [ "$rc_closed" -eq 1 ] \
  || fail "unwritable output exited $rc_full/$rc_fullq/$rc_closed, want 1"
grep -q 'cannot write output: No space left' "$work/full.err" || fail "/dev/full: no message"
grep -q 'cannot write output' "$work/fullq.err" || fail "/dev/full -q: no message"
grep -q 'standard output is closed' "$work/closed.err" || fail "closed stdout: no message"
for f in full fullq closed; do
  [ "$(wc -l < "$work/$f.err")" -eq 1 ] || fail "$f: not exactly one error line"
done

# 5. Bad input: one line on stderr, non-zero exit, nothing on stdout.
check_error() {
  local want=$1; shift
  set +e
  "$tool" "$@" > "$work/err.out" 2> "$work/err.txt"
  local rc=$?
  set -e
  [ "$rc" -eq "$want" ] || fail "'$*' exited $rc, want $want"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || fail "'$*' did not print exactly one error line"
  [ ! -s "$work/err.out" ] || fail "'$*' printed to stdout"
}
check_error 2 bogus:1
check_error 2 'sim:noise=abc'
check_error 2 'sim:script=fly'
check_error 2 -n 0 sim:
check_error 2 --frobnicate sim:
check_error 2
check_error 2 --pty -r "$work/x.rec" sim:
check_error 2 -n 1e30 sim:
check_error 2 'sim:rate=1e-300'
# A bad value names the option and its valid range, in one line (not the usage).
check_error 2 --predict 31 sim:
grep -q -- "--predict: '31' .*0..30" "$work/err.txt" || fail "--predict 31: range not named"
check_error 2 -n 0 sim:
grep -q -- "--count: '0' .*1..1e18" "$work/err.txt" || fail "-n 0: range not named"
# --help: every option with its default, on stdout, exit 0.
"$tool" --help > "$work/help.txt" 2> "$work/help.err" || fail "--help exit"
[ ! -s "$work/help.err" ] && grep -q -- '--timeout S .*\[5\]' "$work/help.txt" \
  || fail "--help: no defaults"
# A source that yields no sample: one error line, exit 1, and the final counters show why.
set +e
"$tool" --stats 0 --timeout 0.5 replay:/dev/zero > "$work/zero.out" 2> "$work/zero.err"
rc=$?
set -e
[ "$rc" -eq 1 ] && [ "$(wc -l < "$work/zero.err")" -eq 1 ] || fail "replay:/dev/zero: want exit 1, one error line"
grep -q '^# stats samples=0 frames=0 garbage_bytes=[1-9]' "$work/zero.out" || fail "replay:/dev/zero: no final stats"
check_error 1 replay:/nonexistent/raystream.rec
# A file that is no recording (a model, a text, an empty file) is refused, not replayed
# as zero samples and exit 0.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$work/model.obj"
check_error 1 "replay:$work/model.obj"
grep -q 'not a recording' "$work/err.txt" || fail "replay of a model: message"
: > "$work/empty.rec"
check_error 1 "replay:$work/empty.rec"
# rate=0 is refused rather than read as the default 120 Hz.
check_error 2 'sim:rate=0'
grep -q 'rate.*0.01' "$work/err.txt" || fail "sim:rate=0: message names the valid range"
check_error 1 serial:/dev/raystream-none
check_error 1 -l /nonexistent/layout.json sim:
check_error 2 --predict 31 sim:
check_error 2 'replay:/nonexistent/x.rec?speed=2'
# --record onto something that is not a regular file (here a FIFO; as root /dev/null
# would be replaced by a regular file) is refused and the node is left as it was.
rm -f "$work/fifo" && mkfifo "$work/fifo"
check_error 1 -n 5 -r "$work/fifo" sim:
[ -p "$work/fifo" ] || fail "--record replaced a FIFO"
echo "track_cli: all checks passed"
