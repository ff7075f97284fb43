# The multibody animation as ParaView shows it (issue 25, item 13): a pvbatch screenshot under
# Xvfb with the arm tube and the point-mass cubes where and as large as they should be, and the
# point fields of a frame against rigid-body kinematics (tests/animation/).
find_program(XVFB_RUN xvfb-run) # .ci/setup installs xvfb; without it the test fails naming XVFB_RUN-NOTFOUND, as for pvbatch
add_test(NAME cli_animation_screenshot_shows_tube_and_point_masses
  COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:flextrack> -DSRC=${CMAKE_SOURCE_DIR}
          -DOUT=${CMAKE_CURRENT_BINARY_DIR}/animation -DXVFB_RUN=${XVFB_RUN} -DPVBATCH=${PVBATCH}
          -P ${CMAKE_CURRENT_SOURCE_DIR}/animation/expect_animation.cmake)
set_tests_properties(cli_animation_screenshot_shows_tube_and_point_masses PROPERTIES LABELS cli)
