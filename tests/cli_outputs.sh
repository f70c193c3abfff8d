#!/bin/sh
# Where the command line writes: an output folder that is missing is created; many bodies stopped by
# Ctrl-C leave nothing (nor the hidden folder they were written into); a command that fails prints
# no table for bodies it never made; a simulated collection keeps its true meshes out of the scans'
# folder, so the folder lists as exactly its scans.
# usage: cli_outputs.sh SSCAPE OUT_DIR
set -u
sscape=$1 out=$2/cli_outputs
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

# A folder that does not exist yet.
"$sscape" synth --random 2 --seed 3 -o "$out/new/deeper/body.ply" > "$out/new.txt" 2>&1 || { cat "$out/new.txt"; fail "synth into a new folder"; }
[ -s "$out/new/deeper/body_000.ply" ] && [ -s "$out/new/deeper/body_001.ply" ] || fail "the bodies in the new folder"
[ -z "$(ls -A "$out/new/deeper" | grep -v '^body_00[01]\.ply$')" ] || fail "something else was left: $(ls -A "$out/new/deeper")"

# Ctrl-C in the middle of many bodies: exit 130 and nothing written.
mkdir -p "$out/many"
"$sscape" synth --random 3000 --seed 1 -o "$out/many/b.ply" > "$out/many.txt" 2> "$out/many.err" &
pid=$!
tries=0
# Once a few bodies exist (in the hidden folder), or after 30 s, Ctrl-C every 0.2 s until it stops.
while kill -0 "$pid" 2> /dev/null && [ "$tries" -lt 300 ]; do
    sleep 0.2
    tries=$((tries + 1))
    staged=$(find "$out/many" -name 'b_*.ply' 2> /dev/null | wc -l)
    if [ "$staged" -ge 3 ] || [ "$tries" -ge 150 ]; then kill -INT "$pid" 2> /dev/null; fi
done
wait "$pid"
status=$?
[ "$status" -eq 130 ] || { cat "$out/many.err"; fail "cancelled synth: exit $status, not 130"; }
grep -q "cancelled (Ctrl-C) after [0-9]* of 3000 bodies; nothing written" "$out/many.err" || { cat "$out/many.err"; fail "the cancel message"; }
[ -z "$(ls -A "$out/many")" ] || fail "a cancelled synth left $(ls -A "$out/many" | head -n 3)"

# A failure met while making the bodies: no table header, nothing written.
"$sscape" synth --random 2 --sliders stature=1e30 -o "$out/failed/b.ply" > "$out/failed.txt" 2>&1 && fail "an absurd slider was accepted"
! grep -q "height_m" "$out/failed.txt" || { cat "$out/failed.txt"; fail "the table's header printed for a failed synth"; }
[ -z "$(ls -A "$out/failed" 2> /dev/null)" ] || fail "a failed synth left $(ls -A "$out/failed")"

# A simulated collection: scans with their landmarks in one folder, the truths in another.
"$sscape" simulate --count 3 --seed 5 --points 2000 -o "$out/collection" > "$out/collection.txt" 2>&1 ||
    { cat "$out/collection.txt"; fail "simulate --count"; }
grep -q "wrote 3 scans with their landmarks to .*/scans and their true meshes to .*/truth" "$out/collection.txt" || fail "the collection's line"
[ "$(ls "$out/collection/scans")" = "$(printf 'sim_001.lnd\nsim_001.ply\nsim_002.lnd\nsim_002.ply\nsim_003.lnd\nsim_003.ply')" ] ||
    fail "the scans folder holds $(ls "$out/collection/scans" | tr '\n' ' ')"
[ "$(ls "$out/collection/truth")" = "$(printf 'sim_001.obj\nsim_002.obj\nsim_003.obj')" ] || fail "the truth folder holds $(ls "$out/collection/truth" | tr '\n' ' ')"
cmp -s "$out/collection/scans/sim_001.ply" "$out/collection/scans/sim_002.ply" && fail "two scans of the collection are the same"
# Its first scan is the single simulation with the same seed.
"$sscape" simulate --seed 5 --points 2000 -o "$out/single" > /dev/null 2>&1 || fail "simulate"
cmp -s "$out/collection/scans/sim_001.ply" "$out/single_scan.ply" || fail "sim_001 differs from simulate --seed 5"
cmp -s "$out/collection/truth/sim_001.obj" "$out/single_truth.obj" || fail "sim_001's truth differs from simulate --seed 5"
echo "outputs: folders created, nothing left by a cancel or a failure, collections apart from their truths"
