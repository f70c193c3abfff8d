#!/usr/bin/env bash
# Tests the Rust crates against a built library (cargo test --offline: no crates from a registry),
# then runs the README's example. Exits 77 (skipped, with the reason) where cargo is missing.
# usage: bindings/rust/test.sh LIBRARY_DIR WORK_DIR
#   env: SSCAPE_SCENARIO_REFERENCE, SSCAPE_LAYOUTS (tests/bindings: the C side of the comparisons)
set -euo pipefail
libdir="$(realpath "$1")" work="$2"
here="$(cd "$(dirname "$0")" && pwd)"
# rustup installs into ~/.cargo/bin, which a non-login shell may not have on its PATH.
[ -d "$HOME/.cargo/bin" ] && PATH="$PATH:$HOME/.cargo/bin"
command -v cargo > /dev/null || { echo "SKIPPED: cargo not found (Debian's cargo, or rustup)"; exit 77; }
mkdir -p "$work"
export CARGO_TARGET_DIR="$work/target" SSCAPE_LIB_DIR="$libdir" LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
cd "$here"
cargo --version
cargo test --offline --locked
# The README's example, as written there.
cargo run --offline --locked --example bodies -- "$work" | tee "$work/example.log"
grep -q "wrote .*body_0.glb" "$work/example.log"
grep -Eq "^sscape [0-9]+\.[0-9]+\.[0-9]+: " "$work/example.log" || { echo "the example's version is not written as major.minor.patch"; exit 1; }
[ -s "$work/body_0.glb" ]
