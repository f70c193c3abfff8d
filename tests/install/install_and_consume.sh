#!/usr/bin/env bash
# Installs a built sscape into a fresh prefix, then builds and runs the C sample against the
# installed copy twice: through CMake's find_package(sscape) and through pkg-config with the README's
# one line (an rpath to the prefix, no LD_LIBRARY_PATH); and a program of the offline tools' API
# (libsscape_offline, sscape_offline.h) both ways too.
# usage: install_and_consume.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build="$1" source="$2" work="$3"
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
sample="$source/samples/c_synthesize/main.c"

cmake --install "$build" --prefix "$prefix" > "$work/install.log"
for f in include/sscape/sscape.h include/sscape/sscape_offline.h share/sscape/models/sscape-default.sscape share/doc/sscape/LICENSE \
         share/doc/sscape/LICENSE-MODELS bin/sscape; do
  [ -f "$prefix/$f" ] || { echo "not installed: $f"; exit 1; }
done
lib=$(find "$prefix" -name 'libsscape.so.0' | head -n 1)
[ -n "$lib" ] || { echo "libsscape.so.0 not installed"; exit 1; }
libdir=$(dirname "$lib")

# The installed command line, on the installed default model file.
"$prefix/bin/sscape" info "$prefix/share/sscape/models/sscape-default.sscape" | grep -q "joints: *53"

# 1. CMake: find_package(sscape) with a version, the imported target sscape::sscape.
cmake -S "$source/tests/install/consumer" -B "$work/cmake-consumer" -DCMAKE_PREFIX_PATH="$prefix" \
      -DSAMPLE_SOURCE="$sample" > "$work/cmake-consumer.log"
cmake --build "$work/cmake-consumer" > "$work/cmake-consumer-build.log"
grep -q "SSCAPE_DEFAULT_MODEL_FILE=$prefix" "$work/cmake-consumer-build.log"
"$work/cmake-consumer/consumer" > "$work/cmake-consumer.out"
"$work/cmake-consumer/consumer" "$prefix/share/sscape/models/sscape-default.sscape" > "$work/cmake-consumer-file.out"

# A version the installed package cannot serve is refused.
sed 's/find_package(sscape 0.1 REQUIRED)/find_package(sscape 1.0 REQUIRED)/' "$source/tests/install/consumer/CMakeLists.txt" \
    > "$work/wrong-version.txt"
mkdir -p "$work/wrong-version"
cp "$work/wrong-version.txt" "$work/wrong-version/CMakeLists.txt"
if cmake -S "$work/wrong-version" -B "$work/wrong-version/build" -DCMAKE_PREFIX_PATH="$prefix" -DSAMPLE_SOURCE="$sample" \
     > "$work/wrong-version.log" 2>&1; then
  echo "find_package(sscape 1.0) accepted the 0.x package"; exit 1
fi

# 2. pkg-config, relocated: the .pc file finds its prefix from its own folder.
export PKG_CONFIG_PATH="$libdir/pkgconfig"
pkg-config --exists --print-errors "sscape >= 0.1"
# The README's line: the rpath makes the program find the library where it was installed.
cc -std=c99 -Wall -Wextra -pedantic -Werror "$sample" -o "$work/pc-consumer" \
   $(pkg-config --cflags --libs sscape) -Wl,-rpath,$(pkg-config --variable=libdir sscape)
env -u LD_LIBRARY_PATH "$work/pc-consumer" > "$work/pc-consumer.out"
[ -f "$(pkg-config --variable=default_model sscape)" ]

# Both consumers ran the same program against the same library.
diff "$work/pc-consumer.out" "$work/cmake-consumer.out"

# 3. The offline tools (libsscape_offline.so, sscape_offline.h), both ways, on a folder of scans.
offline="$source/tests/install/offline_consumer.c"
mkdir -p "$work/scans/truth"
touch "$work/scans/a.ply" "$work/scans/a.lnd" "$work/scans/b.OBJ" "$work/scans/.hidden.ply" "$work/scans/notes.txt" "$work/scans/truth/c.obj"
printf 'scan a with landmarks\nscan b\ndefault model: 13380 vertices\n' > "$work/offline.expected"
cmake -S "$source/tests/install/consumer" -B "$work/cmake-offline" -DCMAKE_PREFIX_PATH="$prefix" -DSAMPLE_SOURCE="$offline" \
      -DSSCAPE_TARGET=sscape::sscape_offline > "$work/cmake-offline.log"
cmake --build "$work/cmake-offline" > "$work/cmake-offline-build.log"
env -u LD_LIBRARY_PATH "$work/cmake-offline/consumer" "$work/scans" > "$work/cmake-offline.out"
diff "$work/offline.expected" "$work/cmake-offline.out"
cc -std=c99 -Wall -Wextra -pedantic -Werror "$offline" -o "$work/pc-offline" \
   $(pkg-config --cflags --libs sscape_offline) -Wl,-rpath,$(pkg-config --variable=libdir sscape_offline)
env -u LD_LIBRARY_PATH "$work/pc-offline" "$work/scans" > "$work/pc-offline.out"
diff "$work/offline.expected" "$work/pc-offline.out"
echo "installed into $prefix; consumers built with find_package and pkg-config ran"
