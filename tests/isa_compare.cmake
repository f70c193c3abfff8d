# Runs `sscape synth` (random posed bodies with normals, glTF and OBJ) once with the kernels the CPU
# offers and once forced to the plain x86-64 ones (SSCAPE_ISA=baseline), and requires identical
# files. Arguments: -DSSCAPE=<cli> -DOUT=<folder>.
file(MAKE_DIRECTORY ${OUT}/native ${OUT}/baseline)
foreach(isa native baseline)
  if(isa STREQUAL baseline)
    set(ENV{SSCAPE_ISA} baseline)
  else()
    unset(ENV{SSCAPE_ISA})
  endif()
  execute_process(COMMAND ${SSCAPE} synth --random 3 --seed 11 --normals --pose "t_pose;head=0.3,0.2,0"
                          -o ${OUT}/${isa}/body.obj RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "sscape synth (${isa}) failed: ${rc}")
  endif()
endforeach()
foreach(i 000 001 002)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/native/body_${i}.obj ${OUT}/baseline/body_${i}.obj
                  RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "body_${i}.obj differs between the native and the baseline kernels")
  endif()
endforeach()
message(STATUS "native and baseline kernels wrote identical bodies")
