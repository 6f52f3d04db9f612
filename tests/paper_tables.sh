#!/usr/bin/env bash
# Usage: paper_tables.sh SCRIPT WORK_DIR BUILD_DIR. tools/paper-tables.sh --quick writes the
# three tables with the paper's figures beside a number of ours in every cell it measures
# (Table 3 with each column's error against the CPU reference tracer), names machine and
# renderer, shows progress, and fails cleanly on a bad option.
source "$(dirname "$0")/cli_harness.sh"
script=$bin
build=$3

# --help is usage on stdout, exit 0.
bash "$script" --help >stdout.txt 2>stderr.txt && grep -q -- '--out FILE.md' stdout.txt &&
  [ ! -s stderr.txt ] && ok "--help" || bad "--help: $(head -c 300 stderr.txt)"
# An output that cannot be written is refused at the start (one line, exit 1, before any
# table is measured), never "wrote" after the work, and nothing is left behind.
# refused NAME TARGET: run with --out TARGET; true when refused cleanly.
refused() {
  local name=$1 target=$2 rc
  bash "$script" --quick --build "$build" --out "$target" >stdout.txt 2>stderr.txt
  rc=$?
  if [ "$rc" -ne 1 ]; then bad "$name: exit $rc, want 1"
  elif [ "$(wc -l <stderr.txt)" -ne 1 ] || grep -q 'Table\|wrote' stderr.txt; then
    bad "$name: want one error line before any work: $(head -c 300 stderr.txt)"
  elif compgen -G "$work/*.tmp-*" >/dev/null || compgen -G "$work/dir/*.tmp-*" >/dev/null; then
    bad "$name: left a temporary file"
  else ok "$name refused: $(cat stderr.txt)"; fi
}
mkdir -p dir
refused "folder as --out" dir
refused "missing folder" "$work/no-such-folder/t.md"
echo x >plain && refused "file as folder" plain/t.md
mkfifo fifo && refused "FIFO as --out" fifo
[ -p fifo ] || bad "FIFO replaced"
# a failure after the start (here: no tools in --build) leaves no output and no temporary
if bash "$script" --build "$work/dir" --out dir/t.md >stdout.txt 2>stderr.txt; then
  bad "missing tools: exit 0"
else
  [ ! -e dir/t.md ] && ! compgen -G "dir/t.md.tmp-*" >/dev/null && ok "failed run leaves nothing" ||
    bad "failed run left $(ls dir)"
fi

if bash "$script" --quick --build "$build" --out tables.md >stdout.txt 2>stderr.txt; then
  ok "quick run"
elif no_gl stderr.txt; then
  skipped "no GL context: $(tail -c 300 stderr.txt)"
  finish
  exit
else
  bad "quick run: $(tail -c 400 stderr.txt)"
fi
[ "$(cat stdout.txt)" = tables.md ] && ok "output named on stdout" ||
  bad "stdout: $(head -c 200 stdout.txt)"
for t in "Table 1" "Table 2" "Table 3"; do
  grep -q "^## $t" tables.md && ok "$t present" || bad "$t missing"
done
# the paper's figures beside ours
for f in 174.652 443.34 646.73 268.77 101.74 3.46 12.79; do
  grep -q -- "$f" tables.md || bad "paper figure $f missing"
done
grep -Eq '^\| box +\| +153 \| +[0-9.]+ \|' tables.md && ok "Table 1 has our hit numbers" ||
  bad "Table 1 row: $(grep '^| box' tables.md | head -1)"
# Table 2 from raystream-bench --table 2 (a row per setting): our fps beside the paper's 443.34
grep -Eq '^\| box +\| tree BVH, 1 pass \| [0-9.]+ .*\| [0-9.]+ \| .*443\.34|^\| box \| [0-9.]+ \([0-9.]+\) \| 443\.34' tables.md &&
  ok "Table 2 has our fps" ||
  bad "Table 2 row: $(grep '^| box' tables.md | tail -1)"
grep -Eq '^\| ours, fps \| [0-9.]+ \| .* \| [0-9.]+ \(hit numbers [0-9.]+\) \| [0-9.]+ \|' tables.md &&
  ok "Table 3 has the ray tracer's fps" || bad "Table 3 row: $(grep '^| ours' tables.md)"
# Table 3 beside the fps: the classic column without shadows (the paper's effects), each
# column's fps over the tracer's, and each column's error against the CPU reference tracer,
# where the GL tracer agrees (fp32 against double) and the unshadowed classic map does not.
grep -q '^| | classic env map | classic env map, reflection only (the paper.s effects: no shadows) |' \
  tables.md && ok "Table 3 has the reflection-only column" || bad "Table 3 header: $(grep '^| | classic' tables.md)"
grep -Eq '^\| ours, fps / the ray tracer.s( \| [0-9.]+){3} \| 1 \| [0-9.]+ \|$' tables.md &&
  ok "Table 3 has fps ratios" || bad "Table 3 ratios: $(grep '^| ours, fps /' tables.md)"
cell='([0-9.]+) dB, max [0-9.]+, [0-9.]+% off'
if [[ "$(grep '^| ours, error' tables.md)" =~ ^\|\ ours,\ error\ against\ the\ CPU\ reference\ tracer\ \|\ $cell\ \|\ $cell\ \|\ $cell\ \|\ $cell\ \|\ the\ reference\ \|$ ]] &&
   awk -v none="${BASH_REMATCH[2]}" -v tracer="${BASH_REMATCH[4]}" \
     'BEGIN { exit !(tracer >= 57 && none < 40) }'; then ok "Table 3 has each column's error"
else bad "Table 3 error row: $(grep '^| ours, error' tables.md)"; fi
grep -q "^Classic environment mapping: rasterized primary hits" tables.md &&
  ok "Table 3's classic column named as rasterized" || bad "Table 3's classic method not named"
grep -q "^Machine: " tables.md && grep -q "llvmpipe\|Renderers: egl: [^;]" tables.md &&
  ok "machine and renderer named" || bad "machine or renderer missing"
[ "$(grep -c '^paper-tables: Table' stderr.txt)" -ge 5 ] && ok "progress shown" ||
  bad "progress: $(cat stderr.txt)"
grep -q "^Speed: the egl columns' fps are medians of 1 round(s)" tables.md &&
  ok "Table 3 says how its speed was taken" || bad "Table 3's speed line missing"
# --rounds N: Table 3's columns N times, alternating; a count outside 1..64 is refused.
if bash "$script" --quick --rounds 2 --build "$build" >rounds.md 2>stderr.txt &&
   grep -q "medians of 2 round(s)" rounds.md && grep -q "round 2 of 2: mirrors, inter-reflection" stderr.txt &&
   grep -Eq '^\| ours, fps / the ray tracer.s( \| [0-9.]+){3} \| 1 \| [0-9.]+ \|$' rounds.md; then
  ok "--rounds 2: two alternating rounds, ratios as medians"
else bad "--rounds 2: $(tail -c 300 stderr.txt)"; fi
for n in 0 65 x; do
  if bash "$script" --quick --rounds "$n" --build "$build" >stdout.txt 2>stderr.txt; then
    bad "--rounds $n accepted"
  else
    rc=$?
    [ "$rc" = 2 ] && grep -q -- "--rounds: '$n' is not a whole number in 1..64" stderr.txt &&
      ok "--rounds $n refused" || bad "--rounds $n: exit $rc, $(cat stderr.txt)"
  fi
done
if bash "$script" --frobnicate >stdout.txt 2>stderr.txt; then bad "bad option accepted"
else grep -q "unknown option '--frobnicate'" stderr.txt && ok "bad option refused" ||
  bad "bad option message: $(cat stderr.txt)"; fi
finish
