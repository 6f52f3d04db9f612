#!/usr/bin/env bash
# Build the protocol parser fuzz harness (tests/fuzz/fuzz_proto.c) with clang-14's
# libFuzzer + ASan + UBSan and run it for a bounded time.
#   tests/fuzz.sh [SECONDS=60] [BUILD_DIR=build-fuzz]
# Exit status: 0 when no crash, leak or invariant failure was found in the time given.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
secs=${1:-60}
out=${2:-$root/build-fuzz}
cc=${RS_FUZZ_CC:-clang-14}
mkdir -p "$out/corpus"
"$cc" -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O1 -g \
  -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -I"$root/lib/include" \
  "$root/tests/fuzz/fuzz_proto.c" "$root/lib/track/proto.c" "$root/lib/core/status.c" "$root/lib/core/assert.c" \
  -lm -o "$out/fuzz_proto"
# Seeds: a raw stream of garbage and a program of valid/corrupt/raw/truncated frames.
printf '\000\001garbage\245Z\001>' > "$out/corpus/seed_raw"
printf '\001\007\000\000\001\005\003\000\002\004abcd\003\000' > "$out/corpus/seed_ops"
# A small quarantine keeps ASan's memory modest on shared machines.
export ASAN_OPTIONS=${ASAN_OPTIONS:-quarantine_size_mb=32:detect_leaks=1}
"$out/fuzz_proto" -max_total_time="$secs" -max_len=4096 -timeout=10 -rss_limit_mb=1024 \
  -artifact_prefix="$out/" -print_final_stats=1 "$out/corpus" > "$out/fuzz.log" 2>&1 || {
  status=$?
  tail -n 60 "$out/fuzz.log"
  echo "fuzz.sh: failure; log in $out/fuzz.log, reproducer in $out/" >&2
  exit "$status"
}
tail -n 6 "$out/fuzz.log"
