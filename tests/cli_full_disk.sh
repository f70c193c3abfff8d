#!/bin/sh
# `sscape bootstrap` onto a disk that fills up mid-round: a clear message and a failing exit, no
# partial file, no model for the round; the same command resumes once there is room, reusing what
# was written. The full disk is a small tmpfs in a private mount namespace (unshare); where this
# machine allows no such mount the test is skipped (exit 77).
# usage: cli_full_disk.sh SSCAPE OUT_DIR
set -u
fail() { echo "FAIL: $*"; exit 1; }

# The inner part, run as root of a private mount namespace: the round's registrations go to a
# disk with room for about two and a half of them (mesh and report, 0.7 MB each); what was written
# there is kept when the namespace ends.
if [ "${1:-}" = "--inside" ]; then
    sscape=$2 out=$3
    registrations=$out/run/round_1/registrations
    mkdir -p "$registrations" && mount -t tmpfs -o size=1700k tmpfs "$registrations" 2> /dev/null || exit 77
    "$sscape" bootstrap "$out/scans" --rounds 1 --components 2 -o "$out/run" > "$out/full.txt" 2>&1
    echo $? > "$out/full_code.txt"
    cp -a "$registrations" "$out/kept"
    umount "$registrations"
    exit 0
fi

sscape=$1 out=$2/full_disk
rm -rf "$out" && mkdir -p "$out/scans"

for i in 1 2 3 4; do
    "$sscape" simulate -o "$out/truth_$i" --seed "$((40 + i))" --points 8000 --pose-amount 0.3 > /dev/null || fail "simulate $i"
    mv "$out/truth_${i}_scan.ply" "$out/scans/b$i.ply" && mv "$out/truth_$i.lnd" "$out/scans/b$i.lnd"
done
if [ "$(id -u)" -eq 0 ] && unshare --mount --propagation private true 2> /dev/null; then
    unshare --mount --propagation private sh "$0" --inside "$sscape" "$out"
elif unshare --mount --map-root-user --propagation private true 2> /dev/null; then
    unshare --mount --map-root-user --propagation private sh "$0" --inside "$sscape" "$out"
else
    echo "SKIPPED: no private mount namespace here (unshare); the full-disk test needs one for its small disk"; exit 77
fi
code=$?
[ "$code" -eq 77 ] && { echo "SKIPPED: a tmpfs cannot be mounted here; the full-disk test needs one"; exit 77; }
[ "$code" -eq 0 ] && [ -s "$out/full_code.txt" ] || fail "the run on the small disk ($code)"
cat "$out/full.txt"
[ "$(cat "$out/full_code.txt")" -eq 1 ] || fail "bootstrap on a full disk exited $(cat "$out/full_code.txt"), not 1"
grep -q "cannot write .*No space left on device" "$out/full.txt" || fail "the message names the full disk"
run=$out/run
rmdir "$run/round_1/registrations" && mv "$out/kept" "$run/round_1/registrations" || fail "keeping the registrations"
[ -s "$run/round_0/model.sscape" ] || fail "no start model"
[ -e "$run/round_1/model.sscape" ] && fail "a model was written for the round that failed"
# A registration is its mesh and its report: the pairs written whole are what a resumed run reuses.
registered=0
for f in "$run/round_1/registrations/"*.json; do
    [ -s "$f" ] && [ -s "${f%.json}.ply" ] && registered=$((registered + 1))
done
[ "$registered" -ge 1 ] && [ "$registered" -lt 4 ] || fail "$registered registrations before the disk filled (expected 1 to 3)"
leftovers=$(find "$run" -type f ! -name "*.ply" ! -name "*.json" ! -name "*.sscape" ! -name "*.csv" ! -name "*.png" ! -name .sscape-lock | wc -l)
[ "$leftovers" -eq 0 ] || { find "$run" -type f; fail "temporary files left behind"; }

# Room again: the same command resumes, reusing every registration that was written.
"$sscape" bootstrap "$out/scans" --rounds 1 --components 2 -o "$run" > "$out/resumed.txt" 2>&1 ||
    { cat "$out/resumed.txt"; fail "the resumed run"; }
grep -q "round 1: $((4 - registered)) registered, $registered reused, 0 failed" "$out/resumed.txt" ||
    { cat "$out/resumed.txt"; fail "the resumed run did not reuse the $registered registrations"; }
[ -s "$run/round_1/model.sscape" ] || fail "no model after resuming"
echo "full disk: refused with a message, nothing partial, resumed"
