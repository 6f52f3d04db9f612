#!/usr/bin/env bash
# Build a protocol parser fuzz harness with clang-14's libFuzzer + ASan + UBSan and run it
# for a bounded time: RS_FUZZ_TARGET=proto (default, tests/fuzz/fuzz_proto.c, the tracker
# protocol) or stream (tests/fuzz/fuzz_stream.c, the remote rendering protocol).
#   [RS_FUZZ_TARGET=stream] tests/fuzz.sh [SECONDS=60] [BUILD_DIR=build-fuzz]
# Exit status: 0 when no crash, leak or invariant failure was found in the time given.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
secs=${1:-60}
out=${2:-$root/build-fuzz}
cc=${RS_FUZZ_CC:-clang-14}
target=${RS_FUZZ_TARGET:-proto}
case "$target" in
  proto) srcs=("$root/lib/track/proto.c") ;;
  stream) srcs=("$root/lib/stream/wire.c" "$root/lib/stream/parser.c") ;;
  *) echo "fuzz.sh: unknown RS_FUZZ_TARGET '$target' (proto or stream)" >&2; exit 2 ;;
esac
out=$out/$target
mkdir -p "$out/corpus"
"$cc" -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O1 -g \
  -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -I"$root/lib/include" -I"$root/lib/core" -I"$root/lib/stream" \
  "$root/tests/fuzz/fuzz_$target.c" "${srcs[@]}" "$root/lib/core/status.c" "$root/lib/core/assert.c" \
  -lm -o "$out/fuzz_$target"
if [ "$target" = proto ]; then
  # Seeds: a raw stream of garbage and a program of valid/corrupt/raw/truncated frames.
  printf '\000\001garbage\245Z\001>' > "$out/corpus/seed_raw"
  printf '\001\007\000\000\001\005\003\000\002\004abcd\003\000' > "$out/corpus/seed_ops"
else
  # Seeds: the documented hello, and a 1x1 raw frame after a byte of garbage.
  printf '\000RS\001\001\016\000\000\000\000\002\000\002\125\003\003\000abcbox' > "$out/corpus/seed_hello"
  printf '\376xRS\001\004\044\000\000\000\001\000\000\000\002\000\000\000\003\000\000\000\000\000\000\000\001\000\001\000\002\000\000\000\000\000\000\000\000\000\000\000\001\002\003\377' > "$out/corpus/seed_frame"
fi
# A small quarantine keeps ASan's memory modest on shared machines.
export ASAN_OPTIONS=${ASAN_OPTIONS:-quarantine_size_mb=32:detect_leaks=1}
"$out/fuzz_$target" -max_total_time="$secs" -max_len=4096 -timeout=10 -rss_limit_mb=1024 \
  -artifact_prefix="$out/" -print_final_stats=1 "$out/corpus" > "$out/fuzz.log" 2>&1 || {
  status=$?
  tail -n 60 "$out/fuzz.log"
  echo "fuzz.sh: failure; log in $out/fuzz.log, reproducer in $out/" >&2
  exit "$status"
}
tail -n 6 "$out/fuzz.log"
