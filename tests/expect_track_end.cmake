# Runs EXE run SCENE -o OUT and requires the end-of-track stop (issue 10): exit status 3 (solver
# failure), the report on stderr matching REGEX, and the rows written before it readable
# (probes.csv and summary.json exist, the last row at the stop time STOP within 1e-6 s).
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND ${EXE} run ${SCENE} -o ${OUT} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "exit status ${rc}; stderr: ${err}")
if(NOT rc EQUAL 3)
  message(FATAL_ERROR "expected exit status 3 (solver failure), got ${rc}")
endif()
if(NOT err MATCHES "${REGEX}")
  message(FATAL_ERROR "stderr does not match '${REGEX}'")
endif()
foreach(f probes.csv summary.json)
  if(NOT EXISTS "${OUT}/${f}")
    message(FATAL_ERROR "${OUT}/${f} is missing: results before the stop must stay readable")
  endif()
endforeach()
file(STRINGS "${OUT}/probes.csv" rows)
list(GET rows -1 last)
string(REGEX MATCH "^[^,]+" t_last "${last}")
# CMake compares no floating-point numbers: the time must start with the 6 digits of STOP.
if(NOT t_last MATCHES "^${STOP}")
  message(FATAL_ERROR "the last output row is at t = ${t_last}, expected the stop at ${STOP}")
endif()
