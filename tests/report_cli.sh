#!/usr/bin/env bash
# Usage: report_cli.sh REPORT_BINARY WORK_DIR. raystream-report --quick on the CPU and, when
# this build has it, EGL (llvmpipe in CI): the CSV has every number, the reference setting
# rendered again has exactly zero error, the Markdown names a pick, the plot is a PNG.
source "$(dirname "$0")/cli_harness.sh"

if "$bin" --help >out.txt 2>err.txt && [ ! -s err.txt ] && grep -q -- '--frames 1..64 .*\[5\]' out.txt &&
    grep -q -- '--backend .*\[auto\]' out.txt; then ok "--help on stdout with defaults"
else bad "--help: $(head -c 300 err.txt)"; fi
fails_cleanly "no output dir" 2 "--out DIR is required" --quick && ok "no output dir"
fails_cleanly "unknown option" 2 "unknown option '--frobnicate'" --frobnicate 1 --out . &&
  ok "unknown option"
fails_cleanly "bad passes" 2 "--max-passes: '9' .*1\.\.5" --max-passes 9 --out . && ok "bad passes"
fails_cleanly "zero frames" 2 "--frames: '0' .*1\.\.64" --frames 0 --out . && ok "zero frames"
fails_cleanly "zero size" 2 "--size: '0' .*8\.\.4096" --size 0 --out . && ok "zero size"
fails_cleanly "bad time" 2 "--time: 'gpu' is not wall\|cpu" --time gpu --out . && ok "bad time"
fails_cleanly "bad backend" 2 "--backend: .*vulkan" --backend vulkan --out . && ok "bad backend"
echo x >plain
fails_cleanly "folder under a file" 1 "plain: exists and is not a folder" --quick --backend cpu \
  --no-plot --out plain/report && ok "folder under a file"
if ls ./*.tmp-* >/dev/null 2>&1; then bad "unwritable dir left a file"; fi
# The README's line: --out report/ is made when it does not exist, and every file written
# is named on stdout.
if "$bin" --quick --backend cpu --no-plot --out new/report/ >new.out 2>new.err &&
    [ -s new/report/report.csv ] && grep -q '^wrote new/report/*report.csv$' new.out &&
    grep -q '^wrote new/report/*report.md$' new.out; then ok "--out folder made, outputs named"
else bad "--out new/report/: $(tail -c 300 new.err) $(cat new.out)"; fi

# check_run NAME DIR: the files of one good run.
check_run() {
  local name=$1 dir=$2
  local csv=$dir/report.csv
  [ -s "$csv" ] || { bad "$name: no CSV"; return; }
  local rows
  rows=$(($(wc -l <"$csv") - 1))
  [ "$rows" -ge 5 ] || { bad "$name: only $rows settings"; return; }
  # 19 fields, numbers 11..18 finite (PSNR may be inf for an exact setting) or all
  # 'refused', none empty
  local broken
  broken=$(awk -F, 'NR > 1 {
      if (NF != 19) { print "line " NR ": " NF " fields"; next }
      for (i = 1; i <= NF; i++) if ($i == "") print "line " NR ": field " i " empty"
      if ($11 == "refused") {  # a setting the backend refuses for this scene: all or none
        for (i = 11; i <= 18; i++) if ($i != "refused") print "line " NR ": field " i " = " $i
        next
      }
      for (i = 11; i <= 18; i++)
        if ($i !~ /^-?[0-9.]+(e[-+]?[0-9]+)?$/ && !(i == 15 && $i == "inf"))
          print "line " NR ": field " i " = " $i
    }' "$csv")
  [ -z "$broken" ] || { bad "$name: $broken"; return; }
  ok "$name: $rows settings, every number present"
  # row 1: the reference setting rendered again by its own renderer
  local self
  self=$(awk -F, 'NR == 2 { print $1 "|" $15 "|" $16 "|" $17 "|" $18 }' "$csv")
  if [ "$self" = "cpu reference (self)|inf|0|0|0" ]; then ok "$name: reference against itself is exact"
  else bad "$name: reference against itself: $self"; fi
  # the reference setting is exact, so the zero budget has a pick, and the front exists
  if grep -q '^| 0.0 % | none' "$dir/report.md"; then bad "$name: no pick for a zero budget"
  elif ! grep -q '| yes |' "$dir/report.md"; then bad "$name: no Pareto front in the table"
  else ok "$name: Markdown names a pick and the front"; fi
  if [ "$(head -c 8 "$dir/report.png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] &&
    [ "$(stat -c %s "$dir/report.png")" -gt 2000 ]; then ok "$name: plot is a PNG"
  else bad "$name: report.png missing or not a PNG"; fi
  # the setting without shadows is measured on every backend (the tracer's and, on GL, the
  # classic environment map's)
  if grep -q "trace 2p no shadows,[a-z]*,[a-z]*,none," "$csv"; then ok "$name: no-shadows setting measured"
  else bad "$name: no 'trace 2p no shadows' row with shadows none"; fi
  if ls "$dir"/*.tmp-* >/dev/null 2>&1; then bad "$name: temporary left behind"; fi
}

mkdir -p cpu egl
if "$bin" --quick --backend cpu --out cpu >cpu.out 2>cpu.err; then check_run cpu cpu
else bad "cpu run: $(tail -c 400 cpu.err)"; fi
if "$bin" --quick --backend egl --time cpu --diffs --out egl >egl.out 2>egl.err; then
  check_run egl egl
  pngs=0
  for f in egl/diff-*.png; do
    [ "$(head -c 8 "$f" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] && pngs=$((pngs + 1))
  done
  [ "$pngs" -eq $(($(wc -l <egl/report.csv) - 1)) ] && grep -q 'diff-00.png' egl/report.md &&
    ok "egl: a difference image per setting" || bad "egl: $pngs difference images"
  grep -q "Pareto (CPU ms)" egl/report.md && ok "egl: front by CPU time" || bad "egl: --time cpu ignored"
  grep -q "raster 2p map" egl/report.csv && grep -q ",map,128,3," egl/report.csv &&
    grep -q ",envmap," egl/report.csv && grep -q "envmap no shadows,egl,trace,none," egl/report.csv &&
    ok "egl: raster, shadow-map and env-map settings measured" || bad "egl: settings missing"
  # A setting the scene cannot have (Cow5 has more mirror objects than inter-reflection
  # maps hold) is a refused row of a complete report, not a failed run.
  mkdir -p refused
  if "$bin" --quick --scene cow5 --backend egl --out refused >refused.out 2>refused.err; then
    check_run refused refused
    grep -q "interreflect:1,.*,refused,refused," refused/report.csv &&
      grep -q "refused: .*mirror objects" refused/report.md &&
      ok "egl: refused settings reported as refused" || bad "egl: refused rows missing"
  else
    bad "cow5 run with refused settings: $(tail -c 400 refused.err)"
  fi
elif no_gl egl.err; then
  skipped "egl: $(tail -c 300 egl.err)"
else
  bad "egl run: $(tail -c 400 egl.err)"
fi
finish
