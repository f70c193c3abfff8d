#!/bin/sh
# An output that is one of the command's inputs (the same path, another spelling of it, a symbolic
# or a hard link to it) is refused before any work, and the input is left as it was: once
# `register scan.ply -o scan.ply`, `fit --points scan.ply -o scan.ply` and `learn --model M -o M`
# replaced the raw scan or the model (issue 47, item 1).
# usage: cli_inputs_kept.sh SSCAPE OUT_DIR MODEL_FILE
set -u
sscape=$1 out=$2/cli_inputs_kept model_file=$3
rm -rf "$out" && mkdir -p "$out/sub"
fail() { echo "FAIL: $*"; exit 1; }
"$sscape" simulate -o "$out/s" --seed 3 --points 3000 > /dev/null 2>&1 || fail "simulate"
cp "$out/s_scan.ply" "$out/original.ply" && cp "$out/s.lnd" "$out/original.lnd"
ln -s s_scan.ply "$out/link.ply"
ln "$out/s_scan.ply" "$out/hard.ply"
refused() {  # refused WHAT COMMAND...: exit 1 or 2, the message, the inputs unchanged
    what=$1; shift
    "$@" > "$out/refused.txt" 2>&1
    code=$?
    { [ "$code" -eq 1 ] || [ "$code" -eq 2 ]; } && grep -q "is the input .*an input is never replaced" "$out/refused.txt" ||
        { cat "$out/refused.txt"; fail "$what: exit $code, or no message naming the input"; }
    cmp -s "$out/s_scan.ply" "$out/original.ply" || fail "$what replaced the scan"
    cmp -s "$out/s.lnd" "$out/original.lnd" || fail "$what replaced the landmarks"
    [ -L "$out/link.ply" ] || fail "$what replaced the link"
}
refused "register -o the scan" "$sscape" register "$out/s_scan.ply" -o "$out/s_scan.ply"
refused "register -o the scan spelled otherwise" "$sscape" register "$out/s_scan.ply" -o "$out/sub/../s_scan.ply"
refused "register -o a link to the scan" "$sscape" register "$out/s_scan.ply" -o "$out/link.ply"
refused "register -o a hard link to the scan" "$sscape" register "$out/s_scan.ply" -o "$out/hard.ply"
cp "$out/s.lnd" "$out/lm.json" && cp "$out/s.lnd" "$out/lm_original.json"
"$sscape" register "$out/s_scan.ply" --landmarks "$out/lm.json" -o "$out/lm.ply" --report "$out/lm.json" > "$out/refused.txt" 2>&1
code=$?
[ "$code" -ne 0 ] && grep -q "is the input .*an input is never replaced" "$out/refused.txt" || { cat "$out/refused.txt"; fail "register's report over its landmarks: exit $code"; }
cmp -s "$out/lm.json" "$out/lm_original.json" && [ ! -e "$out/lm.ply" ] || fail "register replaced its landmarks or wrote the mesh"
refused "fit -o the scan" "$sscape" fit --points "$out/s_scan.ply" -o "$out/s_scan.ply"
refused "fit --params onto a link to the scan" "$sscape" fit --points "$out/s_scan.ply" -o "$out/fit.obj" --params "$out/link.ply"
cp "$model_file" "$out/model.sscape" && cp "$model_file" "$out/model_original.sscape"
if "$sscape" learn --help > /dev/null 2>&1; then
    "$sscape" learn "$out/s_scan.ply" "$out/hard.ply" "$out/original.ply" --model "$out/model.sscape" --components 2 -o "$out/model.sscape" > "$out/refused.txt" 2>&1
    code=$?
    [ "$code" -ne 0 ] && grep -q "is the input .*an input is never replaced" "$out/refused.txt" || { cat "$out/refused.txt"; fail "learn -o its --model: exit $code"; }
    cmp -s "$out/model.sscape" "$out/model_original.sscape" || fail "learn replaced its model"
fi
echo "inputs kept: every output over an input refused"
