#!/usr/bin/env bash
# Usage: streambench_cli.sh STREAMBENCH_BINARY WORK_DIR. raystream-streambench on a tiny
# sequence: it says which link it emulates, shows progress, prints a row per encoding;
# help lists the defaults; bad values are one line naming the option and its range.
source "$(dirname "$0")/cli_harness.sh"

if "$bin" --help >out.txt 2>err.txt && [ ! -s err.txt ] &&
    grep -q -- '--link-mbps .*802.11g.*\[25\]' out.txt && grep -q -- '--frames 2..1000 .*\[30\]' out.txt; then
  ok "--help on stdout with defaults"
else bad "--help: $(head -c 300 out.txt)"; fi
if "$bin" --size 32x32 --frames 3 --qualities 60,90 >out.txt 2>err.txt; then
  grep -q "emulating a 25 Mbit/s link with 5 ms latency" err.txt && ok "link emulation stated" ||
    bad "link not stated: $(head -c 300 err.txt)"
  [ "$(grep -c '^raystream-streambench: \[[0-9]/3\]' err.txt)" -eq 3 ] && ok "progress" ||
    bad "progress: $(cat err.txt)"
  grep -q '^raw ' out.txt && grep -q '^420 q60 ' out.txt && grep -q '^420 q90 ' out.txt &&
    ok "a row per encoding" || bad "rows: $(cat out.txt)"
else bad "tiny run: exit $? $(tail -c 300 err.txt)"; fi
fails_cleanly "zero frames" 2 "--frames: '1' .*2\.\.1000" --frames 1 && ok "zero frames"
fails_cleanly "bad size" 2 "--size: '0x0' is not WxH" --size 0x0 && ok "bad size"
fails_cleanly "bad quality" 2 "--qualities: '0,101'" --qualities 0,101 && ok "bad quality"
fails_cleanly "bad link" 2 "--link-mbps: '0' .*0.001\.\.100000" --link-mbps 0 && ok "bad link"
fails_cleanly "unknown option" 2 "unknown option '--bogus'" --bogus && ok "unknown option"
finish
