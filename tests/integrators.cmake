# Issue 11: the generalised-alpha integrator and `flextrack bench` (its unit tests are in
# tests/unit/multibody_rigid_test.cc and multibody_spin_test.cc).

# flextrack bench on the large-amplitude pendulum (4 s, about 2 s in all): the CSV with its header,
# both sweeps, the plot; generalised-alpha's observed order and IDA's error against its tolerance
# (tests/integrators/check_bench.py says why those references hold).
add_test(NAME cli_bench_writes_work_precision_table_and_plot
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/integrators/check_bench.py ${CMAKE_CURRENT_BINARY_DIR}/cli_bench_pendulum
          --run $<TARGET_FILE:flextrack> ${CMAKE_SOURCE_DIR}/prm/pendulum.prm)
set_tests_properties(cli_bench_writes_work_precision_table_and_plot PROPERTIES LABELS cli TIMEOUT 300
  FAIL_REGULAR_EXPRESSION "FAILED")
