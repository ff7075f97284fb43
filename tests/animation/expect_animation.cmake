# The animation and plots as a user sees them (issue 25, item 13): run arm_and_bead.prm (run.png
# drawn by default), then render and
# read its frames with ParaView (check_animation.py under xvfb-run pvbatch: the tube's and the
# cubes' drawn sizes against the section and the point-like size, the fields against rigid-body
# kinematics). Arguments: EXE, SRC, OUT, XVFB_RUN, PVBATCH.
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND ${EXE} run ${SRC}/tests/animation/arm_and_bead.prm -o ${OUT}/run
  RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "run failed (${rc}): ${log}${err}")
endif()
foreach(line "1 arm: 1 arm tube\\(s\\), 1 point mass cube\\(s\\), deformed" "2 bead: box 0.1 x 0.1 x 0.1 m")
  if(NOT log MATCHES "${line}")
    message(FATAL_ERROR "the log does not say what is drawn ('${line}'):\n${log}")
  endif()
endforeach()
# Output/Plots defaults to true: run.png is drawn and listed (a PNG signature at its start).
file(READ ${OUT}/run/run.png signature LIMIT 8 HEX)
if(NOT signature STREQUAL "89504e470d0a1a0a" OR NOT log MATCHES "results in .*run.png")
  message(FATAL_ERROR "no run.png by default (signature '${signature}'):\n${log}")
endif()
# Up to three tries, each with a fresh X server: under load Xvfb was once not ready for pvbatch
# ("bad X server connection", SIGABRT before any check ran; seen once in a loaded ctest -j 2 run).
# Only that failure is retried: a failed check is final.
foreach(attempt 1 2 3)
  execute_process(COMMAND ${XVFB_RUN} -a ${PVBATCH} ${SRC}/tests/animation/check_animation.py ${OUT}/run ${OUT}/frame0.png
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT err MATCHES "bad X server connection")
    break()
  endif()
  message(STATUS "try ${attempt}: pvbatch found no X server (${rc}); again")
endforeach()
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "the file names the bodies")
  message(FATAL_ERROR "the animation check failed (${rc}); screenshot ${OUT}/frame0.png\n${err}")
endif()
