# Runs laplacian_deform with the default task in the folder OUT and checks its outputs.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${TOOL} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                WORKING_DIRECTORY ${OUT})
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "laplacian_deform failed (${rc}): ${err}")
endif()
foreach(f cactus_vertex-based.off cactus_edge-based.off summary.txt)
  if(NOT EXISTS ${OUT}/laplacian_deform_output/${f})
    message(FATAL_ERROR "missing output ${f}:\n${out}")
  endif()
endforeach()
message(STATUS "${out}")
