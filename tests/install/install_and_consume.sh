#!/usr/bin/env bash
# Installs a built sscape into a fresh prefix, then builds and runs the C sample against the
# installed copy twice: through CMake's find_package(sscape) and through pkg-config.
# usage: install_and_consume.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build="$1" source="$2" work="$3"
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
sample="$source/samples/c_synthesize/main.c"

cmake --install "$build" --prefix "$prefix" > "$work/install.log"
for f in include/sscape/sscape.h share/sscape/models/sscape-default.sscape share/doc/sscape/LICENSE \
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
cc -std=c99 -Wall -Wextra -pedantic -Werror $(pkg-config --cflags sscape) "$sample" -o "$work/pc-consumer" $(pkg-config --libs sscape)
LD_LIBRARY_PATH="$libdir" "$work/pc-consumer" > "$work/pc-consumer.out"
[ -f "$(pkg-config --variable=default_model sscape)" ]

# Both consumers ran the same program against the same library.
diff "$work/pc-consumer.out" "$work/cmake-consumer.out"
echo "installed into $prefix; consumers built with find_package and pkg-config ran"
