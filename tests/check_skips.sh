#!/usr/bin/env bash
# Usage: check_skips.sh CHECK_SKIPS_SCRIPT WORK_DIR. The CI gate on skipped tests
# (tools/check-skips.sh) can fail: a ctest JUnit report (the lines CMake 3.25 writes) with
# a skipped GL test fails it where every test must run, warns elsewhere, and a report
# with none skipped, or a missing one, is told apart.
source "$(dirname "$0")/cli_harness.sh"
gate=$bin
report() { # FILE SKIPPED_NAME...: two tests, those named skipped
  {
    echo '<?xml version="1.0" encoding="UTF-8"?>'
    echo '<testsuite name="(empty)" tests="2" failures="0" disabled="0" skipped="0">'
    for t in test_gl_chain test_core; do
      printf '\t<testcase name="%s" classname="%s" time="0.5" status="%s">\n' "$t" "$t" \
        "$(case " ${*:2} " in *" $t "*) echo notrun ;; *) echo run ;; esac)"
      case " ${*:2} " in *" $t "*) printf '\t\t<skipped message="SKIP_RETURN_CODE=77"/>\n' ;; esac
      # a test's own output, escaped as ctest writes it, must not read as a skip
      printf '\t\t<system-out>&lt;skipped message=&quot;x&quot;/&gt;\n</system-out>\n\t</testcase>\n'
    done
    echo '</testsuite>'
  } >"$1"
}
report skip.xml test_gl_chain
report none.xml
if RS_REQUIRE_ALL_TESTS=1 bash "$gate" skip.xml >out.txt 2>err.txt; then
  bad "a skipped GL test passed the CI gate"
else
  grep -q "test_gl_chain" err.txt && ! grep -q "test_core" err.txt &&
    ok "a skipped GL test fails the CI gate, named" || bad "gate message: $(cat err.txt)"
fi
# the run itself may be under .ci/run, which exports RS_REQUIRE_ALL_TESTS=1
if env -u RS_REQUIRE_ALL_TESTS bash "$gate" skip.xml >out.txt 2>err.txt; then
  grep -q "warning: .*test_gl_chain" err.txt && ok "outside CI a skip is a warning" ||
    bad "no warning: $(cat err.txt)"
else
  bad "outside CI a skip failed the run: $(cat err.txt)"
fi
RS_REQUIRE_ALL_TESTS=1 bash "$gate" none.xml >out.txt 2>err.txt &&
  grep -q "2 tests, none skipped" out.txt && ok "no skip passes" ||
  bad "no skip: $(cat out.txt err.txt)"
if env -u RS_REQUIRE_ALL_TESTS bash "$gate" missing.xml >out.txt 2>err.txt; then bad "a missing report passed"
else ok "a missing report fails"; fi
finish
