#!/bin/sh
# The Python package installed as the README says (a venv over Debian's python3 and numpy, pip
# offline, the built library put into the package), then its tests run against the installed
# package, away from the source tree and without SSCAPE_LIBRARY.
# usage: python_package.sh SOURCE_DIR LIBRARY OUT_DIR
set -eu
src=$1 library=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
cp -r "$src/bindings/python" "$out/package"   # pip builds in the tree it is given: not the source's
/usr/bin/python3 -m venv --system-site-packages "$out/venv"
SSCAPE_LIBRARY="$library" "$out/venv/bin/pip" install --quiet --no-build-isolation --no-index "$out/package"
cp -r "$src/bindings/python/tests" "$out/tests"
cd "$out"
env -u SSCAPE_LIBRARY SSCAPE_SOURCE_DIR="$src" "$out/venv/bin/python" -m pytest -q -p no:cacheprovider tests
"$out/venv/bin/python" -c "import sscape, sys; assert sscape.library_path.startswith('$out/venv'), sscape.library_path; print('installed:', sscape.library_path)"
# The README's Python example, as written there.
"$out/venv/bin/python" - <<'PY'
import sscape
with sscape.Body(sscape.Model()) as body:
    body.set_slider("stature", 1.80)
    vertices, girths = body.vertices, body.measure()   # (13380, 3) float32; a dict, SI units
assert vertices.shape == (13380, 3) and abs(girths["stature"] - 1.80) < 0.01, girths["stature"]
print("the README's example ran")
PY
