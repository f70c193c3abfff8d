#!/usr/bin/env bash
# What a call costs from each language: the same two measurements (a trivial call; a body's
# vertices after a shape change, as an engine asks each frame) from C, Rust, C# and JavaScript,
# each a median of 5 runs, one language after the other on an otherwise idle machine.
# usage: tests/bench/bindings_bench.sh BUILD_DIR      (after ./setup.sh test, which installs the toolchains)
set -euo pipefail
build="$(realpath "$1")" src="$(cd "$(dirname "$0")/../.." && pwd)"
work="$build/bench-bindings" lib="$build/sdk"
mkdir -p "$work"
export LD_LIBRARY_PATH="$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
cc -O2 -std=c99 -I"$src/include" "$src/tests/bindings/bench.c" -L"$lib" -lsscape -o "$work/bench_c"
"$work/bench_c"
[ -d "$HOME/.cargo/bin" ] && PATH="$PATH:$HOME/.cargo/bin"
(cd "$src/bindings/rust" && SSCAPE_LIB_DIR="$lib" CARGO_TARGET_DIR="$work/rust" cargo run --offline --locked --quiet --release --example bench)
mcs -unsafe -optimize+ -target:library -out:"$work/Sscape.dll" "$src"/bindings/csharp/Sscape/*.cs
mcs -optimize+ -r:"$work/Sscape.dll" -out:"$work/Bench.exe" "$src/bindings/csharp/Examples/Bench.cs"
mono "$work/Bench.exe"
NODE_PATH="$build/npm/node_modules" SSCAPE_LIBRARY="$lib/libsscape.so" node "$src/bindings/javascript/examples/bench.js"
