# Compile settings shared by every sscape target.

if(SSCAPE_SANITIZE)
  add_compile_options(-fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined,float-cast-overflow)
endif()

if(SSCAPE_ARCH AND CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  include(CheckCXXCompilerFlag)
  check_cxx_compiler_flag("-march=${SSCAPE_ARCH}" SSCAPE_HAS_ARCH_FLAG)
  if(SSCAPE_HAS_ARCH_FLAG)
    add_compile_options(-march=${SSCAPE_ARCH})
  endif()
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
