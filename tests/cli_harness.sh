# Shared by the tool end-to-end scripts (render_cli.sh, scene_tool.sh); sourced with the
# script's arguments TOOL_BINARY WORK_DIR. Runs in a fresh WORK_DIR, counts checks, and
# `finish` prints "N passed, N failed, N skipped" and fails the script on any failure; a
# part that could not run (`skipped`: no GL context here) makes it exit 77, which ctest
# reports as Skipped where the test has SKIP_RETURN_CODE 77, never as Passed.
set -u
# the scripts' own folder, absolute: sourcing a sibling after the cd below must not depend
# on how the script was named (ctest passes an absolute path, a developer a relative one)
here=$(cd "$(dirname "$0")" && pwd)
bin=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1
passed=0
failed=0
skips=0

ok() { passed=$((passed + 1)); echo "ok: $1"; }
bad() { failed=$((failed + 1)); echo "FAILED: $1"; }
skipped() { skips=$((skips + 1)); echo "SKIPPED: $1"; }
# no_gl FILE: true when FILE (a tool's stderr) says this build or machine has no GL context
no_gl() { grep -Eq "not part of this build|unknown backend '(egl|osmesa)'|no EGL display|no OpenGL" "$1"; }

# fails_cleanly NAME EXIT REGEX ARGS...: run "$bin" ARGS (stdout to stdout.txt, stderr to
# stderr.txt); true when it exits EXIT with exactly one stderr line matching REGEX,
# otherwise the failure is recorded with `bad` and it returns 1.
fails_cleanly() {
  local name=$1 code=$2 regex=$3
  shift 3
  "$bin" "$@" >stdout.txt 2>stderr.txt
  local rc=$?
  local lines
  lines=$(wc -l <stderr.txt)
  if [ "$rc" -ne "$code" ]; then bad "$name: exit $rc, wanted $code ($(head -c 300 stderr.txt))"; return 1; fi
  if [ "$lines" -ne 1 ]; then bad "$name: $lines stderr lines: $(head -c 300 stderr.txt)"; return 1; fi
  if ! grep -Eq -- "$regex" stderr.txt; then bad "$name: message '$(cat stderr.txt)' does not match /$regex/"; return 1; fi
  return 0
}

finish() {
  echo "$passed passed, $failed failed, $skips skipped"
  [ "$failed" -eq 0 ] || return 1
  [ "$skips" -eq 0 ] || return 77
}
