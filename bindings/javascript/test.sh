#!/usr/bin/env bash
# Tests the Node package against a built library, then installs it as its README says and runs the
# README's example. Exits 77 (skipped, with the reason) where node or npm is missing.
# usage: bindings/javascript/test.sh LIBRARY WORK_DIR
#   env: SSCAPE_SCENARIO_REFERENCE, SSCAPE_LAYOUTS (tests/bindings: the C side of the comparisons);
#        NODE_PATH where koffi is installed (setup.sh installs it into BUILD/npm/node_modules)
set -euo pipefail
library="$(realpath "$1")" work="$2"
here="$(cd "$(dirname "$0")" && pwd)"
for tool in node npm; do
  command -v "$tool" > /dev/null || { echo "SKIPPED: $tool not found (Node.js 18 or later and npm run these tests)"; exit 77; }
done
node -e "require('koffi')" 2> /dev/null || { echo "SKIPPED: koffi not found (./setup.sh test installs it with npm)"; exit 77; }
export SSCAPE_LIBRARY="$library"
(cd "$here" && node --test test/ && node --check examples/bench.js)

# The README's installation and example, in a new project.
rm -rf "$work" && mkdir -p "$work/project"
cd "$work/project"
npm init -y > /dev/null
npm install --silent --no-audit --no-fund --prefer-offline --install-links "$here" > "$work/npm.log" 2>&1 \
  || { cat "$work/npm.log"; exit 1; }
node node_modules/sscape/examples/bodies.js "$work" | tee "$work/example.log"
grep -q "wrote .*body_0.glb" "$work/example.log"
grep -Eq "^sscape [0-9]+\.[0-9]+\.[0-9]+: " "$work/example.log" || { echo "the example's version is not written as major.minor.patch"; exit 1; }
[ -s "$work/body_0.glb" ]

# The TypeScript declarations, against the installed package (tsc from NODE_PATH, where setup.sh puts it).
tsc=""
for dir in ${NODE_PATH//:/ }; do [ -x "$dir/.bin/tsc" ] && tsc="$dir/.bin/tsc" && break; done
if [ -n "$tsc" ]; then
  cp "$here/test/types.ts" "$work/project/types.ts"
  "$tsc" --noEmit --strict --module commonjs --target es2020 "$work/project/types.ts"
  echo "index.d.ts: types.ts compiles with $("$tsc" --version)"
else
  echo "SKIPPED: the TypeScript check (no tsc in NODE_PATH; ./setup.sh test installs typescript)"
fi
