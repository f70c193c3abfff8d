#!/bin/sh
# A command's outputs are written all or none (issue 47, item 6): `register` with an unwritable
# report or picture once exited 1 leaving the new mesh, `fit` its body, `evaluate` its CSV and two
# plots. An
# unwritable path is refused before any work; a write that fails midway (a disk that fills between
# the mesh and its report: a small tmpfs in a private mount namespace, where this machine allows
# one) leaves none of the command's files, and a file that was there before stays as it was.
# usage: cli_partial_outputs.sh SSCAPE OUT_DIR SIMULATED (a `sscape simulate` prefix: _scan.ply)
set -u
fail() { echo "FAIL: $*"; exit 1; }

if [ "${1:-}" = "--inside" ]; then  # root of a private mount namespace: a disk with room for the mesh only
    sscape=$2 out=$3 scan=$4
    mkdir -p "$out/small" && mount -t tmpfs -o size=600k tmpfs "$out/small" 2> /dev/null || exit 77
    "$sscape" register "$scan" -o "$out/small/reg.ply" --report "$out/small/reg.json" > "$out/small_log.txt" 2>&1
    echo $? > "$out/small_code.txt"
    ls -A "$out/small" > "$out/small_left.txt"
    umount "$out/small"
    exit 0
fi

sscape=$1 out=$2/cli_partial_outputs scan=$3_scan.ply
rm -rf "$out" && mkdir -p "$out"
echo "not a folder" > "$out/file"
refused() {  # refused WHAT COMMAND...: exit 1 at once, the path named, nothing new in $out
    what=$1; shift
    before=$(ls -A "$out" | tr '\n' ' ')
    "$@" > "$out/log.txt" 2>&1
    code=$?
    [ "$code" -eq 1 ] && grep -q "cannot write '$out/file/" "$out/log.txt" || { cat "$out/log.txt"; fail "$what: exit $code, or no message naming the path"; }
    [ "$(ls -A "$out" | grep -v '^log.txt$' | tr '\n' ' ')" = "$(echo "$before" | tr ' ' '\n' | grep -v '^log.txt$' | grep . | tr '\n' ' ')" ] ||
        { ls -A "$out"; fail "$what left files behind"; }
}
refused "register, picture unwritable" "$sscape" register "$scan" -o "$out/reg.ply" --report "$out/reg.json" --png "$out/file/reg.png"
refused "register, mesh unwritable" "$sscape" register "$scan" -o "$out/file/reg.ply"
refused "fit, parameters unwritable" "$sscape" fit --points "$scan" -o "$out/fit.obj" --params "$out/file/fit.json"
refused "fit, picture unwritable" "$sscape" fit --points "$scan" -o "$out/fit.obj" --png "$out/file/fit.png"
# evaluate checks its outputs before it reads a registration: any existing files stand for them.
refused "evaluate, prefix unwritable" "$sscape" evaluate "$scan" "$scan" "$scan" -o "$out/file/ev"

if [ "$(id -u)" -eq 0 ] && unshare --mount --propagation private true 2> /dev/null; then
    unshare --mount --propagation private sh "$0" --inside "$sscape" "$out" "$scan"
elif unshare --mount --map-root-user --propagation private true 2> /dev/null; then
    unshare --mount --map-root-user --propagation private sh "$0" --inside "$sscape" "$out" "$scan"
else
    echo "partial outputs: refused before the work (no private mount namespace here for the full-disk part)"; exit 0
fi
code=$?
[ "$code" -eq 77 ] && { echo "partial outputs: refused before the work (no tmpfs here for the full-disk part)"; exit 0; }
[ "$code" -eq 0 ] && [ -s "$out/small_code.txt" ] || fail "the run on the small disk ($code)"
[ "$(cat "$out/small_code.txt")" -eq 1 ] && grep -q "No space left on device" "$out/small_log.txt" ||
    { cat "$out/small_log.txt"; fail "register on a disk without room for its report: exit $(cat "$out/small_code.txt")"; }
[ ! -s "$out/small_left.txt" ] || { cat "$out/small_left.txt"; fail "register left the mesh (or a temporary) on the full disk"; }
echo "partial outputs: refused before the work, nothing left by a write that failed midway"
