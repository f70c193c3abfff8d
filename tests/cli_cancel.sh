#!/bin/sh
# Ctrl-C during a long fit cancels it through the progress callback: exit 130, a message, and no
# output file. usage: cli_cancel.sh SSCAPE SCAN.ply OUT_DIR
set -u
sscape=$1 scan=$2 out=$3/cancelled_fit.obj
rm -f "$out"
args=""
for i in 1 2 3 4 5 6 7 8 9 10 11 12; do args="$args --points $scan"; done
# shellcheck disable=SC2086
"$sscape" fit $args --frames -o "$out" > "$3/cancel.out" 2> "$3/cancel.err" &
pid=$!
# A background job starts with SIGINT ignored until the fit installs its handler (after reading the
# files, which takes longer under the sanitizers): Ctrl-C again every 0.2 s until it stops.
tries=0
while kill -0 "$pid" 2> /dev/null && [ "$tries" -lt 300 ]; do
    sleep 0.2
    kill -INT "$pid" 2> /dev/null
    tries=$((tries + 1))
done
wait "$pid"
status=$?
cat "$3/cancel.err"
[ "$status" -eq 130 ] || { echo "exit status $status, not 130"; exit 1; }
grep -q "cancelled" "$3/cancel.err" || { echo "no cancel message"; exit 1; }
[ ! -e "$out" ] || { echo "$out was written"; exit 1; }
echo "cancelled cleanly"
