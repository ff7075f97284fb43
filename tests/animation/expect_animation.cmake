# The animation as a user sees it (issue 25, item 13): run arm_and_bead.prm, then render and
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
execute_process(COMMAND ${XVFB_RUN} -a ${PVBATCH} ${SRC}/tests/animation/check_animation.py ${OUT}/run ${OUT}/frame0.png
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "body_names")
  message(FATAL_ERROR "the animation check failed (${rc}); screenshot ${OUT}/frame0.png\n${err}")
endif()
