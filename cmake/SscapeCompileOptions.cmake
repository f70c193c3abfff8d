# Compile settings shared by every sscape target.

if(SSCAPE_SANITIZE)
  add_compile_options(-fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer -fno-sanitize-recover=undefined,float-cast-overflow)
  add_link_options(-fsanitize=address,undefined,float-cast-overflow)
endif()

# Fuzzing (clang): everything instrumented for coverage and checked by the sanitizers; the fuzz
# targets link libFuzzer's main (tests/fuzz).
if(SSCAPE_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()

if(SSCAPE_ARCH AND CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  include(CheckCXXCompilerFlag)
  check_cxx_compiler_flag("-march=${SSCAPE_ARCH}" SSCAPE_HAS_ARCH_FLAG)
  if(SSCAPE_HAS_ARCH_FLAG)
    add_compile_options(-march=${SSCAPE_ARCH})
  endif()
endif()

# Hardening of what ships: stack protector everywhere, fortified libc calls where optimising
# (glibc needs -O; the sanitizers replace those checks), full RELRO and immediate binding for the
# shared library and programs.
add_compile_options(-fstack-protector-strong)
if(NOT SSCAPE_SANITIZE AND NOT SSCAPE_FUZZ)
  add_compile_options($<$<CONFIG:Release,RelWithDebInfo,MinSizeRel>:-D_FORTIFY_SOURCE=2>)
endif()
add_link_options(-Wl,-z,relro,-z,now)

# Our own targets: warnings on, hidden symbols, position-independent (they go into the .so).
function(sscape_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  set_target_properties(${target} PROPERTIES
    POSITION_INDEPENDENT_CODE ON
    CXX_VISIBILITY_PRESET hidden
    C_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
endfunction()

# The command line's and the tests' own files parse arguments, check results and call the
# libraries; CLI11's and Catch's header-only code is most of what they compile. At -O0 they build
# in a third of the time (the sanitizer build: 1010 of its 2360 CPU seconds at -O2), and no hot
# loop lives in them. Only with SSCAPE_UNOPTIMIZED_CLIENTS: the shipped command is optimized.
function(sscape_client_defaults target)
  sscape_defaults(${target})
  if(SSCAPE_UNOPTIMIZED_CLIENTS)
    target_compile_options(${target} PRIVATE -O0 -U_FORTIFY_SOURCE)
  endif()
endfunction()
