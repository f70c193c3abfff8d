# The runtime as WebAssembly (emcmake cmake ...; docs/web.md): the same sources and C API as
# libsscape.so, built by Debian's emscripten. Only the runtime: no command line, training, pictures,
# tests or samples.
#
# Dependencies without a WebAssembly build in Debian:
#   header-only libraries (Eigen, FlatBuffers, nlohmann/json, nanoflann, xxHash): Debian's headers,
#     reached through a folder of links to each one, because adding /usr/include itself would put
#     glibc's headers in front of emscripten's libc;
#   zstd: compiled here from the zstd sources the npm registry serves inside the zstd-napi package
#     (SSCAPE_NPM_MODULES; setup.sh installs it), so the model file is checked and
#     decompressed by the very calls the native library makes;
#   flatc: the host's (it only generates C++ from the schema).

foreach(off SSCAPE_BUILD_CLI SSCAPE_BUILD_TRAINING SSCAPE_BUILD_PICTURES SSCAPE_BUILD_TESTS SSCAPE_BUILD_BENCHMARKS
            SSCAPE_BUILD_SAMPLES SSCAPE_SANITIZE SSCAPE_FUZZ)
  set(${off} OFF CACHE BOOL "off in the WebAssembly build" FORCE)
endforeach()

# npm packages (setup.sh installs them, pinned, into build-wasm/npm): zstd-napi for zstd's sources,
# three for the configurator page.
set(SSCAPE_NPM_MODULES "" CACHE PATH "node_modules with zstd-napi@0.0.13 and three@0.170.0 (setup.sh: build-wasm/npm/node_modules)")
set(SSCAPE_ZSTD_SOURCE ${SSCAPE_NPM_MODULES}/zstd-napi/deps/zstd/lib)
set(SSCAPE_THREE ${SSCAPE_NPM_MODULES}/three)
if(NOT EXISTS "${SSCAPE_ZSTD_SOURCE}/decompress/zstd_decompress.c" OR NOT EXISTS "${SSCAPE_THREE}/build/three.module.min.js")
  message(FATAL_ERROR "SSCAPE_NPM_MODULES='${SSCAPE_NPM_MODULES}' lacks zstd-napi or three: "
                      "npm install --prefix build-wasm/npm zstd-napi@0.0.13 three@0.170.0, then -DSSCAPE_NPM_MODULES=$PWD/build-wasm/npm/node_modules")
endif()

# The host's header-only libraries, each linked into one folder.
set(host_headers ${CMAKE_BINARY_DIR}/host-headers)
file(MAKE_DIRECTORY ${host_headers})
foreach(entry "Eigen=/usr/include/eigen3/Eigen" "flatbuffers=/usr/include/flatbuffers" "nlohmann=/usr/include/nlohmann"
              "nanoflann.hpp=/usr/include/nanoflann.hpp" "xxhash.h=/usr/include/xxhash.h")
  string(REPLACE "=" ";" pair "${entry}")
  list(GET pair 0 name)
  list(GET pair 1 target)
  if(NOT EXISTS "${target}")
    message(FATAL_ERROR "${target} not found: install Debian's libeigen3-dev libflatbuffers-dev nlohmann-json3-dev libnanoflann-dev libxxhash-dev")
  endif()
  file(CREATE_LINK "${target}" "${host_headers}/${name}" SYMBOLIC)
endforeach()

add_library(Eigen3::Eigen INTERFACE IMPORTED)
target_include_directories(Eigen3::Eigen SYSTEM INTERFACE ${host_headers})
add_library(nlohmann_json::nlohmann_json INTERFACE IMPORTED)
target_include_directories(nlohmann_json::nlohmann_json SYSTEM INTERFACE ${host_headers})
set(SSCAPE_FLATBUFFERS_INCLUDE ${host_headers} CACHE PATH "" FORCE)
set(SSCAPE_XXHASH_INCLUDE ${host_headers} CACHE PATH "" FORCE)
find_program(SSCAPE_FLATC flatc REQUIRED NO_CMAKE_FIND_ROOT_PATH)
find_package(Threads REQUIRED)  # no threads in this build (the pool runs inline); std::thread's header only

# zstd (decompression and compression: the container's writer is linked but unused by the runtime's
# exports, and the linker drops it).
file(GLOB zstd_sources ${SSCAPE_ZSTD_SOURCE}/common/*.c ${SSCAPE_ZSTD_SOURCE}/decompress/*.c ${SSCAPE_ZSTD_SOURCE}/compress/*.c)
add_library(sscape_wasm_zstd STATIC ${zstd_sources})
target_include_directories(sscape_wasm_zstd SYSTEM PUBLIC ${SSCAPE_ZSTD_SOURCE})
target_compile_definitions(sscape_wasm_zstd PRIVATE ZSTD_DISABLE_ASM ZSTD_NO_TRACE XXH_NAMESPACE=ZSTD_)
target_compile_options(sscape_wasm_zstd PRIVATE -w)
add_library(zstd::libzstd_static ALIAS sscape_wasm_zstd)

# Everything: WebAssembly SIMD (Chromium, Firefox, Safari and Node all run it), exceptions as
# WebAssembly exceptions (the C API's guard catches the library's errors; emscripten's default
# would abort instead). Not emscripten's SSE2 emulation: Eigen's SSE2 code holds x86 inline
# assembly for the GCC versions clang claims to be (docs/web.md, "Same bits?").
add_compile_options(-msimd128 -fwasm-exceptions)
add_link_options(-fwasm-exceptions)
