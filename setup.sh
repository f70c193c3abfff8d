#!/usr/bin/env bash
# sscape setup: installs the Debian packages the build needs, builds, and runs a job.
#   ./setup.sh         install, build the library and the command line (Release), run the main job:
#                      random bodies of the default model
#   ./setup.sh test    install, build everything (tests, benchmarks, samples), run the whole test suite,
#                      also under ASan + UBSan, then fuzz; prints each stage's time at the end
# Environment: JOBS (parallel build jobs, default: number of cores), FUZZ_SECONDS (per fuzz target,
# default 10), SSCAPE_CCACHE=0 (compile without ccache).
set -euo pipefail
cd "$(dirname "$0")"

mode="${1:-run}"
case "$mode" in run|test) ;; *) echo "usage: $0 [run|test]" >&2; exit 2 ;; esac
jobs="${JOBS:-$(nproc)}"

# Stage times, printed at the end (also when a stage fails).
stage_names=() stage_seconds=()
stage_start=$SECONDS stage_name=""
stage() {  # stage NAME: closes the running stage, starts NAME
  if [ -n "$stage_name" ]; then stage_names+=("$stage_name"); stage_seconds+=($((SECONDS - stage_start))); fi
  stage_name="$1" stage_start=$SECONDS
}
print_stages() {
  local rc=$? i
  stage ""
  echo "setup: stage times ($mode, $([ "$rc" -eq 0 ] && echo passed || echo "FAILED, exit $rc")):"
  for i in "${!stage_names[@]}"; do
    printf 'setup:   %-28s %4d min %02d s\n' "${stage_names[i]}" $((stage_seconds[i] / 60)) $((stage_seconds[i] % 60))
  done
  printf 'setup:   %-28s %4d min %02d s\n' total $((SECONDS / 60)) $((SECONDS % 60))
}
trap print_stages EXIT

stage "Debian packages"
packages=(cmake ninja-build ccache g++ pkg-config libeigen3-dev libnanoflann-dev libflatbuffers-dev flatbuffers-compiler
          libzstd-dev libxxhash-dev libpng-dev nlohmann-json3-dev libcli11-dev libmeshoptimizer-dev)
# The test suite also builds the tests (Catch2) and benchmarks (Google Benchmark), fuzzes with clang's
# libFuzzer, and tests the Python package (Debian's python3) and the C#, Rust and JavaScript bindings.
if [ "$mode" = test ]; then packages+=(catch2 libbenchmark-dev clang libclang-rt-14-dev python3-numpy python3-pytest python3-venv
                                     python3-setuptools python3-wheel python3-distributed python3-tqdm)
  # The bindings' toolchains: Mono for C#; cargo for Rust unless rustup's is there; Node.js for JavaScript.
  packages+=(mono-mcs mono-runtime)
  command -v cargo > /dev/null 2>&1 || [ -x "$HOME/.cargo/bin/cargo" ] || packages+=(cargo)
  command -v node > /dev/null 2>&1 || packages+=(nodejs npm)
  # Blender (headless) tests the Blender add-on and imports the GLB files.
  packages+=(blender)
  # The browser runtime: emscripten builds the library as WebAssembly (its JavaScript optimizer needs
  # Debian's acorn), headless Chromium runs the configurator page (docs/web.md).
  packages+=(emscripten node-acorn chromium)
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

# Ninja, and ccache with its cache outside the clone (ccache's own default, ~/.cache/ccache): a
# second build of the same sources, in this clone or another one (paths are taken relative to the
# clone, CCACHE_BASEDIR), compiles nothing again. Nested builds of the tests (the runtime-only build,
# the install consumers) take both from the environment, as CMake does.
export CMAKE_GENERATOR="${CMAKE_GENERATOR:-Ninja}"
if [ "${SSCAPE_CCACHE:-1}" != 0 ] && command -v ccache > /dev/null 2>&1; then
  export CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache
  # Depend mode: a miss costs no extra preprocessor run (the compiler's -MD list is the manifest).
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true CCACHE_DEPEND=true CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-10G}"
fi

build() {  # build DIR [cmake args...]; TARGET="a b" builds only those targets
  local dir="$1"; shift
  echo "setup: building in $dir"
  local generator_args=()
  # A folder configured earlier keeps its generator (CMake refuses to switch).
  if [ -f "$dir/CMakeCache.txt" ]; then
    generator_args=(-G "$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$dir/CMakeCache.txt")")
  fi
  mkdir -p "$dir"
  # CMAKE_WRAPPER: emcmake for the WebAssembly build (its toolchain file).
  ${CMAKE_WRAPPER:-} cmake -S . -B "$dir" "${generator_args[@]}" "$@" > "$dir.configure.log" 2>&1 || { cat "$dir.configure.log"; exit 1; }
  # shellcheck disable=SC2086
  cmake --build "$dir" -j "$jobs" ${TARGET:+--target $TARGET}
}

# npm packages (pinned): the Khronos glTF validator for the export test; koffi and TypeScript for the
# JavaScript binding's tests (bindings/javascript), three.js for importing the GLB as a web viewer
# would and puppeteer-core for driving Chromium in the browser test, which only the Release build
# runs. The WebAssembly build takes zstd's sources from zstd-napi and three.js for its page.
gltf_validator=gltf-validator@2.0.0-dev.3.10
npm_tools() {  # npm_tools DIR PACKAGE@VERSION...
  local dir="$1" missing_packages=() p; shift
  for p in "$@"; do [ -d "$dir/npm/node_modules/${p%@*}" ] || missing_packages+=("$p"); done
  if [ "${#missing_packages[@]}" -eq 0 ]; then return; fi
  if command -v npm > /dev/null 2>&1; then
    echo "setup: installing npm packages ${missing_packages[*]} into $dir/npm"
    # NPM_IGNORE_SCRIPTS=1: packages taken for their files only (no native addon is built).
    npm install --silent --no-audit --no-fund ${NPM_IGNORE_SCRIPTS:+--ignore-scripts} --prefix "$dir/npm" "$@" > /dev/null 2>&1 \
      || { echo "setup: npm install of $* failed" >&2; exit 1; }
  else
    echo "setup: npm not found; the tests that need $* will be skipped"
  fi
}

# The main build: Release. The main job needs only the library and the command line; the test
# command adds the tests, benchmarks and samples to the same folder (the same objects, reused).
with_tests=OFF
[ "$mode" = test ] && with_tests=ON
release_args=(-DCMAKE_BUILD_TYPE=Release -DSSCAPE_BUILD_TESTS=$with_tests -DSSCAPE_BUILD_BENCHMARKS=$with_tests
              -DSSCAPE_BUILD_SAMPLES=$with_tests)

if [ "$mode" = run ]; then
  stage "build (library, command)"
  # libsscape.so (the runtime), libsscape_offline.so (with the scan tools, for the Python pipeline),
  # the sscape command.
  TARGET="sscape sscape_offline sscape_cli" build build "${release_args[@]}"
  stage "main job"
  mkdir -p out
  # The main job: random bodies of the default model (built into the library) as OBJ, glTF and a picture.
  ./build/bin/sscape info
  ./build/bin/sscape synth --random 5 --seed 1 --normals -o out/body.obj --png out/bodies.png
  ./build/bin/sscape synth --random 5 --seed 1 -o out/body.glb
  echo "setup: bodies written to out/ (body_*.obj, body_*.glb, bodies.png)"
else
  stage "Release build"
  build build "${release_args[@]}"
  stage "WebAssembly build"
  # The runtime, the browser package and the configurator page in build-wasm/web (docs/web.md); the
  # Release tests run it in Chromium.
  NPM_IGNORE_SCRIPTS=1 npm_tools build-wasm zstd-napi@0.0.13 three@0.170.0
  # Archives made by LLVM's ar itself, which emscripten's emar wraps in a Python start of 2 s each.
  llvm_root=$(em-config LLVM_ROOT 2> /dev/null || true)
  [ -x "$llvm_root/llvm-ar" ] && [ -x "$llvm_root/llvm-ranlib" ] || llvm_root=""
  NODE_PATH=/usr/share/nodejs CMAKE_WRAPPER=emcmake build build-wasm -DCMAKE_BUILD_TYPE=Release -DSSCAPE_NPM_MODULES="$PWD/build-wasm/npm/node_modules" \
      ${llvm_root:+-DCMAKE_AR="$llvm_root/llvm-ar" -DCMAKE_RANLIB="$llvm_root/llvm-ranlib"}
  stage "npm packages"
  npm_tools build "$gltf_validator" koffi@3.3.4 typescript@5.9.3 three@0.170.0 puppeteer-core@24.40.0
  stage "Release tests"
  (cd build && ctest -j "$jobs" --output-on-failure)
  stage "sanitizer build"
  # Line tables only (-g1): enough for the sanitizers' reports, 15 % less compile time than -g.
  lines_only=(-DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG")
  # The command line's and the tests' own files at -O0 (SSCAPE_UNOPTIMIZED_CLIENTS), the libraries at
  # -O2. (A unity build of it was tried: 23 minutes against 19 file by file on this machine.)
  build build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo "${lines_only[@]}" -DSSCAPE_SANITIZE=ON -DSSCAPE_BUILD_BENCHMARKS=OFF \
      -DSSCAPE_UNOPTIMIZED_CLIENTS=ON
  npm_tools build-sanitize "$gltf_validator"
  stage "sanitizer tests"
  (cd build-sanitize && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest -j "$jobs" --output-on-failure)
  # The fuzz targets (model loading, each reader), 10 seconds each (two at a time; a regression check with the
  # corpus earlier runs left); long runs: see README.
  stage "fuzz build"
  CC=clang CXX=clang++ TARGET=fuzz_all build build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo "${lines_only[@]}" -DSSCAPE_FUZZ=ON \
      -DSSCAPE_BUILD_TESTS=OFF -DSSCAPE_BUILD_BENCHMARKS=OFF -DSSCAPE_BUILD_TRAINING=OFF -DSSCAPE_BUILD_SAMPLES=OFF
  stage "fuzzing"
  tests/fuzz/run.sh build-fuzz "${FUZZ_SECONDS:-10}"
fi
