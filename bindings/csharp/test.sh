#!/usr/bin/env bash
# Builds the C# binding with Mono's compiler (mcs) and runs its tests under mono against a built
# library, then builds and runs the README's example as written there. Exits 77 (skipped, with the
# reason) where mcs or mono is missing.
# usage: bindings/csharp/test.sh LIBRARY_DIR WORK_DIR
#   env: SSCAPE_SCENARIO_REFERENCE, SSCAPE_LAYOUTS (tests/bindings: the C side of the comparisons)
set -euo pipefail
libdir="$(realpath "$1")" work="$2"
here="$(cd "$(dirname "$0")" && pwd)"
for tool in mcs mono; do
  command -v "$tool" > /dev/null || { echo "SKIPPED: $tool not found (Debian's mono-mcs and mono-runtime)"; exit 77; }
done
rm -rf "$work" && mkdir -p "$work"
export LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" SSCAPE_SOURCE="$here/../.."
# -warnaserror: no warning in our code.
mcs -unsafe -warn:4 -warnaserror -target:library -out:"$work/Sscape.dll" "$here"/Sscape/*.cs
mcs -unsafe -warn:4 -warnaserror -r:"$work/Sscape.dll" -out:"$work/Tests.exe" "$here/Tests/Tests.cs"
mono "$work/Tests.exe"
if [ -n "${SSCAPE_FAKE_ABI_LIBRARY:-}" ]; then
  LD_LIBRARY_PATH="$(dirname "$SSCAPE_FAKE_ABI_LIBRARY")" mono "$work/Tests.exe" --expect-abi-mismatch
fi
# The README's example, as written there.
cd "$work"
mcs -r:Sscape.dll -out:Bodies.exe "$here/Examples/Bodies.cs"
mono Bodies.exe "$work" | tee "$work/example.log"
mcs -r:Sscape.dll -warn:4 -warnaserror -out:Bench.exe "$here/Examples/Bench.cs"  # builds (tests/bench/bindings_bench.sh runs it)
grep -q "wrote .*body_0.glb" "$work/example.log"
grep -Eq "^sscape [0-9]+\.[0-9]+\.[0-9]+: " "$work/example.log" || { echo "the example's version is not written as major.minor.patch"; exit 1; }
[ -s "$work/body_0.glb" ]
