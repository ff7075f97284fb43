# A reduced body file cut after 4 KiB must be refused by 'flextrack inspect' with a clear message
# and a non-zero exit (issue 4, bad input: a corrupted HDF5 file given as a reduced body).
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND ${EXE} reduce ${PRM} -o ${OUT} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "reduce failed: ${err}")
endif()
execute_process(COMMAND head -c 4096 ${OUT}/reduced_body.h5 OUTPUT_FILE ${OUT}/truncated.h5 RESULT_VARIABLE rc)
execute_process(COMMAND ${EXE} inspect ${OUT}/truncated.h5 RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "exit status ${rc}; stderr: ${err}")
if(rc EQUAL 0 OR NOT err MATCHES "truncated.h5: not a valid reduced body: .*(damaged|truncated)")
  message(FATAL_ERROR "the truncated file was not refused clearly")
endif()
