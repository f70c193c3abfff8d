#!/bin/sh
# Landmark names (issue 47, item 9): a .lnd listing a name twice is refused by `fit` and `register`
# with both lines named and nothing written (it was used as 146 landmarks); a name the model does
# not know reaches the user as a warning on stderr (the CLI had no log sink, so `register` dropped
# it silently) and the command goes on without it.
# usage: cli_landmark_names.sh SSCAPE OUT_DIR SIMULATED (a `sscape simulate` prefix: .lnd, _scan.ply)
set -u
sscape=$1 out=$2/cli_landmark_names sim=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
# Every row again, 300 mm higher, before END.
{ sed '/^END/,$d' "$sim.lnd"; sed -n '/^AUX =/,/^END/p' "$sim.lnd" | sed '1d;$d' | awk '{ $6 = $6 + 300; print }'; echo "END ="; } > "$out/twice.lnd"
sed 's/ Sellion$/ Selion/' "$sim.lnd" > "$out/misspelt.lnd"
grep -q " Selion$" "$out/misspelt.lnd" || fail "the test's misspelt file has no misspelt name"

for command in "fit --landmarks $out/twice.lnd -o $out/twice_fit.obj" \
               "register $sim""_scan.ply --landmarks $out/twice.lnd -o $out/twice_reg.ply"; do
    # shellcheck disable=SC2086
    "$sscape" $command > "$out/log.txt" 2>&1
    code=$?
    [ "$code" -eq 1 ] && grep -q "landmark 'Sellion' is listed twice (first on line" "$out/log.txt" ||
        { cat "$out/log.txt"; fail "$command: exit $code, or no message naming the name listed twice"; }
done
[ -z "$(ls "$out" | grep -v '\.lnd$\|log.txt')" ] || { ls "$out"; fail "a refused command wrote something"; }

"$sscape" fit --landmarks "$out/misspelt.lnd" -o "$out/fit.obj" > /dev/null 2> "$out/fit_err.txt" || { cat "$out/fit_err.txt"; fail "fit with a misspelt name failed"; }
grep -q "warning: .*misspelt.lnd: landmark 'Selion' is not one of the model's; ignored" "$out/fit_err.txt" || { cat "$out/fit_err.txt"; fail "fit: no warning naming the misspelt landmark"; }
"$sscape" register "$sim""_scan.ply" --landmarks "$out/misspelt.lnd" -o "$out/reg.ply" > /dev/null 2> "$out/reg_err.txt" ||
    { cat "$out/reg_err.txt"; fail "register with a misspelt name failed"; }
grep -q "warning: .*misspelt.lnd: landmark 'Selion' is not one of the model's; ignored" "$out/reg_err.txt" || { cat "$out/reg_err.txt"; fail "register: no warning naming the misspelt landmark"; }
echo "landmark names: duplicates refused, unknown names warned"
