#!/usr/bin/env bash
# Install, build and run every test: the README's test command, and what CI runs.
# The suite runs under AddressSanitizer and UndefinedBehaviorSanitizer with -Werror; then
# the Release configuration users build (-O3, no sanitizers) must compile with -Werror
# too (other warnings appear at -O3: maybe-uninitialized, stringop-*).
# A test that could not run (a GL test without a context) is Skipped, never Passed;
# with RS_REQUIRE_ALL_TESTS=1 (.ci/run sets it: CI has llvmpipe and Xvfb) a skip fails.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/tools/deps.sh"
bash "$root/tools/check-format.sh"
bash "$root/tools/check-includes.sh"
bash "$root/tools/check-mechanisms.sh"
build=${RS_TEST_BUILD_DIR:-$root/build-test}
jobs=$(nproc)
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRS_WERROR=ON -DRS_SANITIZE=ON
cmake --build "$build" -j"$jobs"
(cd "$build" && ctest --output-on-failure -j"$jobs" --timeout 900 --output-junit "$build/ctest.xml")
bash "$root/tools/check-skips.sh" "$build/ctest.xml"
# Release, -Werror, no sanitizers: built, and its cmocka tests (test_*) run: the fast part
# of the suite (65 tests, about 90 s of CPU time, 1.5 min on 2 cores), and the optimised
# code users get. The tool end-to-end scripts repeat what the sanitized run checked and
# are left out here, to keep the whole script within 15 minutes on a quiet 2-core machine.
release=${RS_TEST_RELEASE_DIR:-$root/build-test-release}
cmake -S "$root" -B "$release" -DCMAKE_BUILD_TYPE=Release -DRS_WERROR=ON -DRS_SANITIZE=OFF
cmake --build "$release" -j"$jobs"
(cd "$release" && ctest --output-on-failure -j"$jobs" --timeout 900 -R '^test_' \
  --output-junit "$release/ctest.xml")
bash "$root/tools/check-skips.sh" "$release/ctest.xml"
