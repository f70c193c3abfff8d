#!/usr/bin/env bash
# sscape setup: installs the Debian packages the build needs, builds, and runs a job.
#   ./setup.sh         install, build (Release), run the main job: random bodies of the default model
#   ./setup.sh test    install, build, run the whole test suite, also under ASan + UBSan, then fuzz
# Environment: JOBS (parallel build jobs, default: number of cores), FUZZ_SECONDS (per fuzz target, default 30).
set -euo pipefail
cd "$(dirname "$0")"

mode="${1:-run}"
case "$mode" in run|test) ;; *) echo "usage: $0 [run|test]" >&2; exit 2 ;; esac
jobs="${JOBS:-$(nproc)}"

packages=(cmake make g++ pkg-config libeigen3-dev libnanoflann-dev libflatbuffers-dev flatbuffers-compiler
          libzstd-dev libxxhash-dev libpng-dev nlohmann-json3-dev libcli11-dev catch2 libbenchmark-dev)
# The test suite also fuzzes, with clang's libFuzzer, and tests the Python package (Debian's python3)
# and the C#, Rust and JavaScript bindings.
if [ "$mode" = test ]; then packages+=(clang libclang-rt-14-dev python3-numpy python3-pytest python3-venv python3-setuptools python3-wheel
                                     python3-distributed python3-tqdm)
  # The bindings' toolchains: Mono for C#; cargo for Rust unless rustup's is there; Node.js for JavaScript.
  packages+=(mono-mcs mono-runtime)
  command -v cargo > /dev/null 2>&1 || [ -x "$HOME/.cargo/bin/cargo" ] || packages+=(cargo)
  command -v node > /dev/null 2>&1 || packages+=(nodejs npm)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all Debian packages present"
fi

build() {  # build DIR [cmake args...]; TARGET=name builds only that target
  local dir="$1"; shift
  echo "setup: building in $dir"
  cmake -S . -B "$dir" "$@" > "$dir.configure.log" 2>&1 || { cat "$dir.configure.log"; exit 1; }
  cmake --build "$dir" -j "$jobs" ${TARGET:+--target "$TARGET"}
}

# npm packages (pinned): the Khronos glTF validator for the export test; koffi and TypeScript for the
# JavaScript binding's tests (bindings/javascript), which only the Release build runs.
gltf_validator=gltf-validator@2.0.0-dev.3.10
npm_tools() {  # npm_tools DIR PACKAGE@VERSION...
  local dir="$1" missing_packages=() p; shift
  for p in "$@"; do [ -d "$dir/npm/node_modules/${p%@*}" ] || missing_packages+=("$p"); done
  if [ "${#missing_packages[@]}" -eq 0 ]; then return; fi
  if command -v npm > /dev/null 2>&1; then
    echo "setup: installing npm packages ${missing_packages[*]} into $dir/npm"
    npm install --silent --no-audit --no-fund --prefix "$dir/npm" "$@" > /dev/null 2>&1 \
      || { echo "setup: npm install of $* failed" >&2; exit 1; }
  else
    echo "setup: npm not found; the tests that need $* will be skipped"
  fi
}

if [ "$mode" = run ]; then
  build build -DCMAKE_BUILD_TYPE=Release
  mkdir -p out
  # The main job: random bodies of the default model (built into the library) as OBJ, glTF and a picture.
  ./build/bin/sscape info
  ./build/bin/sscape synth --random 5 --seed 1 --normals -o out/body.obj --png out/bodies.png
  ./build/bin/sscape synth --random 5 --seed 1 -o out/body.glb
  echo "setup: bodies written to out/ (body_*.obj, body_*.glb, bodies.png)"
else
  build build -DCMAKE_BUILD_TYPE=Release
  npm_tools build "$gltf_validator" koffi@3.3.4 typescript@5.9.3
  (cd build && ctest -j "$jobs" --output-on-failure)
  # Line tables only (-g1): enough for the sanitizers' reports, 15 % less compile time than -g.
  lines_only=(-DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG")
  # The command line's and the tests' own files at -O0 (SSCAPE_UNOPTIMIZED_CLIENTS), the libraries at
  # -O2. (A unity build of it was tried: 23 minutes against 19 file by file on this machine.)
  build build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo "${lines_only[@]}" -DSSCAPE_SANITIZE=ON -DSSCAPE_BUILD_BENCHMARKS=OFF \
      -DSSCAPE_UNOPTIMIZED_CLIENTS=ON
  npm_tools build-sanitize "$gltf_validator"
  (cd build-sanitize && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest -j "$jobs" --output-on-failure)
  # The fuzz targets (model loading, each reader), half a minute each (two at a time); long runs: see README.
  CC=clang CXX=clang++ TARGET=fuzz_all build build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo "${lines_only[@]}" -DSSCAPE_FUZZ=ON \
      -DSSCAPE_BUILD_TESTS=OFF -DSSCAPE_BUILD_BENCHMARKS=OFF -DSSCAPE_BUILD_TRAINING=OFF -DSSCAPE_BUILD_SAMPLES=OFF
  tests/fuzz/run.sh build-fuzz "${FUZZ_SECONDS:-30}"
fi
