# Benchmark of the laser robot (issue 10, Performance; label bench, not in the default run):
# prm/laser_robot.prm for 10 s with cached bodies, total wall time (median of 3, /usr/bin/time -v,
# process start-up included) and peak memory beside the laser head's position error against a
# reference run (24 normal modes, 16 track stations, rtol 1e-9) for several bases and tolerances;
# tests/bench/laser_robot_bench.py, results in doc/benchmarks.md. The reference run (several
# minutes) is kept in the output folder and reused while its scene files are unchanged.
add_test(NAME bench_laser_robot
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/bench/laser_robot_bench.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/bench_laser_robot)
set_tests_properties(bench_laser_robot PROPERTIES LABELS bench TIMEOUT 5400 FAIL_REGULAR_EXPRESSION "benchmark failed")

# Issue 24: the laser robot's work-precision with its default integrator (no tuned Integrator
# settings: Method = auto chooses Radau IIA), rtol 1e-3 ... 1e-10 against rtol 1e-11, one run
# each (about 50 s): every run completes, the error falls with the tolerance at a slope of at
# least 0.7, CPU(1e-8) / CPU(1e-5) at most 5 (tests/bench/laser_robot_work_precision.py).
add_test(NAME bench_laser_robot_work_precision
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/bench/laser_robot_work_precision.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/bench_laser_robot_work_precision)
set_tests_properties(bench_laser_robot_work_precision PROPERTIES LABELS bench TIMEOUT 1800
  FAIL_REGULAR_EXPRESSION "FAILED|benchmark failed")
