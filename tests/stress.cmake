# Numerical stability, issue 11 item 4 (label stress; doc/stress.md): long runs and randomised
# perturbations. The stiff-mode study is in tests/integrators.cmake, bitwise reruns in fuzz.cmake.
# Each test takes 10-40 s in Release on one core; with FLEXTRACK_TIME_LIMIT_FACTOR = 8 (the Debug +
# sanitizer build, tests/CMakeLists.txt) the scripts do an eighth of the work.

# 1. 1000 s runs, IDA and generalised-alpha (tests/stress/long_runs.py says what is asserted and
#    why): constraint drift and |p| - 1 below 10 (rtol L + atol) and not growing (last 100 s
#    against the first 100 s), the energy balance within rtol x steps and growing at most
#    linearly; the torque-free body's angular momentum too. Release: torque-free body 6 s,
#    pendulum 18 s, flexible rod pendulum 23 s.
foreach(case torque_free_body pendulum flexible_rod_pendulum)
  add_test(NAME stress_long_run_${case}_stays_at_tolerance
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/stress/long_runs.py $<TARGET_FILE:flextrack>
            ${CMAKE_CURRENT_BINARY_DIR}/stress_long_runs/${case} ${case})
  set_tests_properties(stress_long_run_${case}_stays_at_tolerance PROPERTIES LABELS stress TIMEOUT 1800)
endforeach()

# 2. 30 randomised runs (fixed seeds) of six scenes: each completes with finite results or stops
#    with a clear solver-failure message (exit 3, time named, results readable); never a crash, a
#    hang (120 s per run; the slowest, seed 1017, takes 10-12 s, 35 s on the loaded machine) or NaN.
#    Release: about 30 s.
add_test(NAME stress_randomised_scenes_complete_or_fail_cleanly
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/stress/perturbations.py $<TARGET_FILE:flextrack>
          ${CMAKE_CURRENT_BINARY_DIR}/stress_perturbations)
set_tests_properties(stress_randomised_scenes_complete_or_fail_cleanly PROPERTIES LABELS stress TIMEOUT 1800)
