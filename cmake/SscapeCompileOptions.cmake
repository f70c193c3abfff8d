# Compile settings shared by every sscape target.

if(SSCAPE_SANITIZE)
  add_compile_options(-fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer -fno-sanitize-recover=undefined,float-cast-overflow)
  add_link_options(-fsanitize=address,undefined,float-cast-overflow)
  # Programs linked at fixed addresses: a sanitized program carries 2.4 million dynamic relocations
  # (the sanitizers' per-check data), which a position-independent one applies at every start,
  # 0.22 of its 0.46 s; the test command starts several hundred of them.
  add_link_options($<$<STREQUAL:$<TARGET_PROPERTY:TYPE>,EXECUTABLE>:-no-pie>)
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

# Objects name their sources relative to the checkout (__FILE__, debug info): the same bytes from
# any clone, so a compiler cache (setup.sh uses ccache) shares them between clones, and a build is
# reproducible wherever it was made.
add_compile_options(-ffile-prefix-map=${PROJECT_SOURCE_DIR}/=)

# Hardening of what ships: stack protector everywhere, fortified libc calls where optimising
# (glibc needs -O; the sanitizers replace those checks), full RELRO and immediate binding for the
# shared library and programs.
# (WebAssembly has neither: its linear memory holds no return addresses or relocations.)
if(NOT EMSCRIPTEN)
  add_compile_options(-fstack-protector-strong)
  if(NOT SSCAPE_SANITIZE AND NOT SSCAPE_FUZZ)
    add_compile_options($<$<CONFIG:Release,RelWithDebInfo,MinSizeRel>:-D_FORTIFY_SOURCE=2>)
  endif()
  add_link_options(-Wl,-z,relro,-z,now)
endif()

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
    # Run once every target exists (the end of the top-level CMakeLists); a deferred call reads
    # its arguments when it runs, so the target's name goes in as a literal.
    cmake_language(EVAL CODE "cmake_language(DEFER DIRECTORY [[${PROJECT_SOURCE_DIR}]] CALL sscape_link_optimized_first [[${target}]])")
  endif()
endfunction()

# The -O0 files instantiate Eigen's and our headers' inline functions too, and a static link keeps
# the first copy it meets: the client's own objects come first, so the -O2 libraries' calls that the
# sanitizers kept from inlining went to -O0 copies. Loading the target's own static libraries
# whole, ahead of its objects, makes their copies the ones kept; the usual link line after them
# resolves the rest. The sanitizer ctest: 873 s against 1,105 s (1,708 against 2,210 summed; the
# C API registration test 59 against 98 s alone).
function(sscape_link_optimized_first target)
  set(pending ${target})
  set(seen "")
  set(archives "")
  while(pending)
    list(POP_FRONT pending item)
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" item "${item}")
    if(NOT TARGET ${item} OR item IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${item})
    get_target_property(type ${item} TYPE)
    if(item STREQUAL target)
      get_target_property(deps ${item} LINK_LIBRARIES)
    elseif(type STREQUAL "STATIC_LIBRARY" OR type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(deps ${item} INTERFACE_LINK_LIBRARIES)
      get_target_property(imported ${item} IMPORTED)
      if(type STREQUAL "STATIC_LIBRARY" AND NOT imported)
        list(APPEND archives $<TARGET_FILE:${item}>)
      endif()
    else()
      continue()
    endif()
    if(deps)
      list(APPEND pending ${deps})
    endif()
  endwhile()
  if(archives)
    target_link_options(${target} PRIVATE -Wl,--whole-archive ${archives} -Wl,--no-whole-archive)
  endif()
endfunction()
