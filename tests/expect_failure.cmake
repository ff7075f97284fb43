# Runs EXE with ARGS (a ;-list) and requires: a non-zero exit, stderr matching REGEX, and no
# output folder OUT (nothing written). ARGS gets "-o OUT" appended unless it has its own -o.
separate_arguments(arg_list UNIX_COMMAND "${ARGS}")
file(REMOVE_RECURSE "${OUT}")
if(NOT ARGS MATCHES " -o ")
  list(APPEND arg_list -o ${OUT})
endif()
execute_process(COMMAND ${EXE} ${arg_list}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "exit status ${rc}; stderr: ${err}")
if(rc EQUAL 0)
  message(FATAL_ERROR "expected a non-zero exit status")
endif()
if(NOT err MATCHES "${REGEX}")
  message(FATAL_ERROR "stderr does not match '${REGEX}'")
endif()
if(EXISTS "${OUT}")
  message(FATAL_ERROR "results were written to ${OUT} although the run failed")
endif()
