# Issue 9 acceptance: the same flexible scene with a Craig-Bampton and a free-interface body
# (tests/cb_vs_fi/cb_vs_fi.py: the references, the bounds and why, beside each assertion). Each
# case's scenes and reduced body go under the binary dir. About 22 s in Release (18 runs); label cli.
add_test(NAME cli_run_craig_bampton_and_free_interface_bodies_converge_to_the_same_motion
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/cb_vs_fi/cb_vs_fi.py $<TARGET_FILE:flextrack>
          ${CMAKE_CURRENT_BINARY_DIR}/cb_vs_fi
  WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli_run_craig_bampton_and_free_interface_bodies_converge_to_the_same_motion
  PROPERTIES LABELS cli TIMEOUT 900) # the Debug + sanitizer build is about 10 times slower
