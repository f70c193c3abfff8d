#!/usr/bin/env bash
# Configures and builds sscape as an engine that only wants the runtime would: no command line,
# training, pictures, tests, benchmarks or samples. The build needs only Eigen, FlatBuffers and zstd
# (and the header-only nanoflann, xxHash and nlohmann-json, the last for the glTF writer), and the
# library it makes depends on nothing but the C and C++ runtimes.
# usage: runtime_only.sh SOURCE_DIR WORK_DIR
set -euo pipefail
source="$1" work="$2"
rm -rf "$work"
cmake -S "$source" -B "$work" -DCMAKE_BUILD_TYPE=Release -DSSCAPE_BUILD_CLI=OFF -DSSCAPE_BUILD_TRAINING=OFF \
      -DSSCAPE_BUILD_PICTURES=OFF -DSSCAPE_BUILD_TESTS=OFF -DSSCAPE_BUILD_BENCHMARKS=OFF -DSSCAPE_BUILD_SAMPLES=OFF \
      > "$work.configure.log"
# Nothing optional was even looked for.
if grep -Ei "PNG|Catch|benchmark" "$work/CMakeCache.txt" | grep -v "^SSCAPE_BUILD\|^//" | grep -q "_DIR:\|FOUND"; then
  echo "the runtime-only configuration looked for an optional dependency:"; grep -Ei "PNG|Catch|benchmark" "$work/CMakeCache.txt"; exit 1
fi
cmake --build "$work" -j "${JOBS:-2}" > "$work.build.log"
lib="$work/sdk/libsscape.so"
[ -f "$lib" ]
needed=$(readelf -d "$lib" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | sort | tr '\n' ' ')
for n in $needed; do
  case "$n" in libc.so.*|libm.so.*|libstdc++.so.*|libgcc_s.so.*|ld-linux*) ;;
    *) echo "libsscape.so needs $n"; exit 1 ;;
  esac
done
[ ! -e "$work/bin/sscape" ] || { echo "the command line was built"; exit 1; }
# Exactly the C API is exported.
if nm -D --defined-only "$lib" | awk '$2 != "A" {print $3}' | grep -v '^ssc_' | grep -q .; then
  echo "libsscape.so exports more than ssc_*"; nm -D --defined-only "$lib" | grep -v ' ssc_'; exit 1
fi
echo "runtime-only build: libsscape.so needs only: $needed"
