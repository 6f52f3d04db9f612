#!/usr/bin/env bash
# Install, build and run every test: the README's test command, and what CI runs.
# The suite runs under AddressSanitizer and UndefinedBehaviorSanitizer with -Werror.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/tools/deps.sh"
bash "$root/tools/check-format.sh"
bash "$root/tools/check-includes.sh"
build=${RS_TEST_BUILD_DIR:-$root/build-test}
jobs=$(nproc)
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRS_WERROR=ON -DRS_SANITIZE=ON
cmake --build "$build" -j"$jobs"
cd "$build"
ctest --output-on-failure -j"$jobs" --timeout 900
