# Issue 13: the worked examples of doc/exports.md are what the exporter writes. The script
# reduces and exports each scene the document names (from the source folder, so the recorded
# scene path is the documented one) and compares every marked block with the file. Label cli.
add_test(NAME cli_mbdyn_doc_examples_match_the_exporter
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/python/check_mbdyn_doc_examples.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/mbdyn_doc_examples)
set_tests_properties(cli_mbdyn_doc_examples_match_the_exporter PROPERTIES LABELS cli)

# Issue 28: a supported body on a revolute joint. 'flextrack export --mbdyn-clamp auto|yes|no'
# (default auto: clamped as before; no: no clamp; a wrong value exits with 2), and the pendulum
# example of doc/exports.md: its .elm excerpt is the exporter's, its MBDyn model agrees as text
# with prm/flexible_pendulum.prm. MBDyn is not a Debian package: only if an 'mbdyn' executable is
# found (or given as -DMBDYN_EXECUTABLE=...) is the model run and its tip compared with
# 'flextrack run' (the tolerance the document states).
find_program(MBDYN_EXECUTABLE mbdyn)
set(mbdyn_for_test "")
if(MBDYN_EXECUTABLE)
  set(mbdyn_for_test ${MBDYN_EXECUTABLE})
endif()
add_test(NAME cli_mbdyn_clamp_option_and_pendulum_example
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/python/check_mbdyn_pendulum_example.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/mbdyn_pendulum_example "${mbdyn_for_test}")
set_tests_properties(cli_mbdyn_clamp_option_and_pendulum_example PROPERTIES LABELS cli)
flextrack_bad_input(export_unknown_mbdyn_clamp "entry '--mbdyn-clamp': unknown value 'maybe'.*allowed: auto, yes, no"
                    export --format mbdyn --mbdyn-clamp maybe input/foreign.h5)
flextrack_bad_input(export_mbdyn_clamp_for_vtu "entry '--mbdyn-clamp': applies to '--format mbdyn' only"
                    export --format vtu --mbdyn-clamp no input/foreign.h5)
