#!/bin/sh
# catch_discover_tests cuts a test name at a semicolon (CMake's list separator), and the cut name
# matches no test, which then passes without running anything: no test name may hold one.
# usage: test_names.sh SSCAPE_TESTS
names=$("$1" --list-test-names-only)  # Catch 2 exits with the number listed
[ -n "$names" ] || { echo "FAIL: no tests listed"; exit 1; }
if printf '%s\n' "$names" | grep -F ';'; then
    echo "FAIL: the test names above hold a semicolon; ctest would run nothing for them"
    exit 1
fi
echo "$(printf '%s\n' "$names" | wc -l) test names, none with a semicolon"
