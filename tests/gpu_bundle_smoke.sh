#!/usr/bin/env bash
# Usage: gpu_bundle_smoke.sh BUNDLER WORK_DIR. tools/gpu-bundle.sh makes the archive a GPU
# machine without our packages runs (its own Release build, no OSMesa); every library but
# the C and C++ runtimes resolves from the archive itself; tools/gpu-device-run.sh --quick
# runs it on this machine's EGL and leaves the report, its log and the target line's JSON;
# a failing step, a missing or foreign bundle and an unwritable output each stop it with a
# non-zero exit and one line, never an exit 0 without the output.
source "$(dirname "$0")/cli_harness.sh"
bundler=$bin
runner=$(dirname "$bundler")/gpu-device-run.sh
runtime='^(linux-vdso|ld-linux|libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|libgcc_s|libstdc\+\+)\.so'

if bash "$bundler" --build build-gpu --out bundle/rs.tar.gz >stdout.txt 2>stderr.txt; then
  ok "bundle made ($(tail -n 1 stderr.txt))"
else
  bad "bundler: $(tail -n 3 stderr.txt)"
  finish
  exit
fi
[ "$(cat stdout.txt)" = bundle/rs.tar.gz ] && ok "stdout names the archive" || bad "stdout: $(cat stdout.txt)"
mkdir x && tar -C x -xzf bundle/rs.tar.gz && ok "archive unpacks" || bad "archive does not unpack"
for f in build/tools/bench/raystream-bench bin/jq MANIFEST lib/libEGL.so.1; do
  [ -e "x/$f" ] && ok "holds $f" || bad "missing $f"
done
grep -Eq '^needs: glibc with GLIBC_[0-9.]+' x/MANIFEST && ok "manifest names the glibc it needs" ||
  bad "manifest: $(cat x/MANIFEST)"
ls x/lib | grep -Eq '^lib(OSMesa|LLVM)' && bad "OSMesa/LLVM packed: $(ls x/lib)" || ok "no OSMesa/LLVM"
ls x/lib | grep -Eq "$runtime" && bad "a runtime packed: $(ls x/lib)" || ok "the runtimes left to the machine"
# Self-contained: with only the archive's folder added, every library resolves there or is
# a runtime; none is missing.
LD_LIBRARY_PATH=$PWD/x/lib ldd x/build/tools/bench/raystream-bench x/bin/jq >ldd.txt 2>&1
grep -q "not found" ldd.txt && bad "unresolved: $(grep 'not found' ldd.txt)" || ok "nothing unresolved"
outside=$(awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' ldd.txt | while read -r name path; do
  [[ $name =~ $runtime ]] || [[ $path == "$PWD/x/lib/"* ]] || echo "$name=$path"; done)
[ -z "$outside" ] && ok "every other library from the archive" || bad "from the machine: $outside"

# The device run, --quick, on this machine's EGL.
mkdir out
bash "$runner" --quick --bundle bundle/rs.tar.gz --out out --platform auto >stdout.txt 2>stderr.txt
rc=$?
if [ "$rc" -ne 0 ] && grep -q "no egl context" out/gpu-run.log 2>/dev/null; then
  skipped "no GL context: $(tail -c 300 stderr.txt)"
  finish
  exit
fi
[ "$rc" -eq 0 ] && ok "device run --quick" || bad "device run: exit $rc: $(tail -c 400 stderr.txt)"
report=$(head -n 1 stdout.txt)
case $report in out/paper-tables-*.md) ok "report $report" ;; *) bad "stdout: $(cat stdout.txt)" ;; esac
[ -s "$report" ] && grep -q "^## Table 2" "$report" && ok "report has the tables" || bad "report: '$report'"
[ "$(sed -n 2p stdout.txt)" = out/gpu-run.log ] && ok "stdout names the log" || bad "stdout: $(cat stdout.txt)"
for want in "^# bundle source: " "^# nvidia-smi: " "raystream-bench --help" "gpu-bench.sh --quick" \
  "--table 2 --backend egl --scene cow17 --lights 4"; do
  grep -Eq -- "$want" out/gpu-run.log && ok "log has /$want/" || bad "log lacks /$want/"
done
jq -e '.rows | length > 0' out/table2-cow17-4lights.json >/dev/null 2>&1 &&
  ok "target line's JSON has rows" || bad "no target JSON rows"
grep -Eq -- "--times --backend egl --passes 2 --lights 4 --size 64 --repeats 1 --kernels compute" \
  out/gpu-run.log && ok "log has the compute times" || bad "log lacks the compute times"
jq -e '[.rows[] | select(.scene == "cow17" and .kernels == "compute" and .fps > 0)] | length == 1' \
  out/times-cow17-4lights.json >/dev/null 2>&1 &&
  jq -e '[.rows[] | select(.kernels == "fragment" and .fps > 0)] | length == 1' \
    out/times-cow17-4lights.json >/dev/null 2>&1 &&
  ok "times JSON has a fragment and a compute row" || bad "times JSON: $(head -c 300 out/times-cow17-4lights.json)"

# A step that fails (Table 2 refused by the packed bench): non-zero, the step named, and
# no target JSON claimed.
mkdir fake
tar -C fake -xzf bundle/rs.tar.gz
mv fake/build/tools/bench/raystream-bench fake/build/tools/bench/real-bench
cat >fake/build/tools/bench/raystream-bench <<'EOS'
#!/usr/bin/env bash
case " $* " in *" --table 2 "*) echo "bench: injected failure" >&2; exit 3 ;; esac
exec "$(dirname "$0")/real-bench" "$@"
EOS
chmod +x fake/build/tools/bench/raystream-bench
tar -C fake -czf bundle/fake.tar.gz .
mkdir out2
if bash "$runner" --quick --bundle bundle/fake.tar.gz --out out2 --platform auto >stdout.txt 2>stderr.txt; then
  bad "failing step: exit 0"
else
  [ "$(wc -l <stderr.txt)" -eq 2 ] && grep -q "^gpu-device-run: Tables 1-3" stderr.txt &&
    grep -q "^gpu-device-run: tools/gpu-bench.sh failed: .* (the whole output: out2/gpu-run.log)" stderr.txt &&
    ok "failing step named in one line after the progress line" ||
    bad "failing step: $(cat stderr.txt)"
fi
[ ! -e out2/table2-cow17-4lights.json ] && ok "no target JSON after the failure" || bad "target JSON written"

# Bad input: one line each, non-zero.
one_line() { # NAME EXIT REGEX CMD...
  local name=$1 code=$2 regex=$3
  shift 3
  "$@" >stdout.txt 2>stderr.txt
  local rc=$?
  [ "$rc" -eq "$code" ] && [ "$(wc -l <stderr.txt)" -eq 1 ] && grep -Eq "$regex" stderr.txt &&
    [ ! -s stdout.txt ] && ok "$name" || bad "$name: exit $rc: $(cat stderr.txt)"
}
one_line "missing bundle" 1 "no bundle at nowhere.tar.gz" bash "$runner" --bundle nowhere.tar.gz --out out
echo hello >note.txt
tar -czf foreign.tar.gz note.txt
one_line "foreign archive" 1 "is not a tools/gpu-bundle.sh archive" bash "$runner" --bundle foreign.tar.gz --out out
one_line "unwritable output" 1 "cannot write to /nonexistent" bash "$runner" --bundle bundle/rs.tar.gz --out /nonexistent
one_line "unknown option" 2 "unknown option '--fast'" bash "$runner" --fast
one_line "bundler: not .tar.gz" 2 "does not end in .tar.gz" bash "$bundler" --out b.zip
one_line "bundler: output folder refused" 1 "cannot write to /proc/rs-gpu" bash "$bundler" --out /proc/rs-gpu/b.tar.gz
one_line "bundler: build folder refused" 1 "cannot make /proc/rs-gpu" bash "$bundler" --build /proc/rs-gpu --out b.tar.gz
finish
