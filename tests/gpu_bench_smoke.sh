#!/usr/bin/env bash
# Usage: gpu_bench_smoke.sh SCRIPT WORK_DIR BUILD_DIR. tools/gpu-bench.sh --quick on this
# machine's EGL (llvmpipe here, the device platform where it opens): the report is written
# under the renderer's name, non-empty, with the machine, renderer, commands, load and the
# tables; a bench that fails part-way makes it exit non-zero and leaves no report (an older
# one stays as it was) and no temporary file.
source "$(dirname "$0")/cli_harness.sh"
script=$bin
build=$3
real_bench=$build/tools/bench/raystream-bench
mkdir -p report

# quick PLATFORM: one --quick run into report/; its exit status
quick() {
  bash "$script" --quick --build "$build" --platform "$1" --out-dir report >stdout.txt 2>stderr.txt
}
platform=device
quick device
rc=$?
if [ "$rc" -ne 0 ] && grep -q "no egl context on platform device" stderr.txt; then
  platform=auto # no EGL device platform here: the first platform that opens
  quick auto
  rc=$?
fi
if grep -q "no egl context" stderr.txt; then
  skipped "no GL context: $(tail -c 300 stderr.txt)"
  finish
  exit
fi
[ "$rc" -eq 0 ] && ok "quick run ($platform)" || bad "quick run: exit $rc: $(tail -c 400 stderr.txt)"
out=$(cat stdout.txt)
case $out in
  report/paper-tables-*.md) ok "report named $out" ;;
  *) bad "stdout: $(head -c 200 stdout.txt)" ;;
esac
[ -s "$out" ] && ok "report non-empty" || bad "no report at '$out'"
base=${out#report/paper-tables-}
[[ $base =~ ^[a-z0-9.-]+\.md$ ]] && ok "file name sanitised: $base" || bad "file name: $base"
for want in "^# The paper's tables on " "^- Machine: " "^- Renderer string" "^- Commands: " \
  "^- Load average" "^## Table 1" "^## Table 2" "^## Table 3" "^\| ours, fps \| [0-9.]+ "; do
  grep -Eq "$want" "$out" && ok "has /$want/" || bad "missing /$want/"
done
cp "$out" before.md

# A bench that fails part-way (Table 2 here; the renderer probe still works): non-zero exit,
# the older report untouched, no temporary file.
mkdir -p fake/tools/bench
cat >fake/tools/bench/raystream-bench <<EOS
#!/usr/bin/env bash
case " \$* " in *" --table 2 "*) echo "bench: injected failure" >&2; exit 3 ;; esac
exec "$real_bench" "\$@"
EOS
chmod +x fake/tools/bench/raystream-bench
if bash "$script" --quick --build fake --platform "$platform" --out-dir report >stdout.txt 2>stderr.txt; then
  bad "failing bench: exit 0"
else
  ok "failing bench: exit non-zero ($(tail -n 1 stderr.txt))"
fi
cmp -s before.md "$out" && ok "older report untouched" || bad "older report changed"
compgen -G "report/*.tmp-*" >/dev/null && bad "temporary file left: $(ls report)" || ok "no temporary file"
rm -f "$out"
if bash "$script" --quick --build fake --platform "$platform" --out-dir report >stdout.txt 2>stderr.txt; then
  bad "failing bench (no older report): exit 0"
fi
[ -z "$(ls report)" ] && ok "failed run leaves nothing" || bad "failed run left $(ls report)"

bash "$script" --platform x11 >stdout.txt 2>stderr.txt
[ $? -eq 2 ] && grep -q "not device, gbm, surfaceless or auto" stderr.txt &&
  [ "$(wc -l <stderr.txt)" -eq 1 ] && ok "bad platform refused in one line" ||
  bad "bad platform: $(cat stderr.txt)"
finish
