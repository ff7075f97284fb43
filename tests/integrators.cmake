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

# Numerical stability (issue 11 item 4, label stress, about 20 s): an undamped 1e5 Hz mode next to
# slow rigid motion, IDA at maximum order 1 ... 5 and generalised-alpha at rho_inf 0 ... 1.
add_test(NAME stress_stiff_mode_next_to_slow_motion
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/stress/stiff_modes.py $<TARGET_FILE:flextrack>
          ${CMAKE_CURRENT_BINARY_DIR}/stress_stiff_modes)
set_tests_properties(stress_stiff_mode_next_to_slow_motion PROPERTIES LABELS stress TIMEOUT 900)

# Issue 11 acceptance: `flextrack bench prm/bench/slewing_beam.prm` (label bench, about 75 s, most
# of it the reference at rtol 1e-11): CSV with reference settings and error definition, PNG;
# generalised-alpha's order between steps 1/32 s and 1/64 s (measured 1.99).
add_test(NAME bench_slewing_beam_work_precision_of_both_integrators
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/integrators/check_bench.py ${CMAKE_CURRENT_BINARY_DIR}/bench_slewing_beam_integrators
          --run $<TARGET_FILE:flextrack> ${CMAKE_SOURCE_DIR}/prm/bench/slewing_beam.prm --order-rows 5 6)
set_tests_properties(bench_slewing_beam_work_precision_of_both_integrators PROPERTIES LABELS bench TIMEOUT 1800
  FAIL_REGULAR_EXPRESSION "FAILED")

# Generalised-alpha finds the end of a track like IDA (tests/tracks.cmake): s(t) = 0.3 + t on an
# arm of 0.6 pi / 2 m ends at t = 0.6424778 s (closed form); the stop time within 1e-6 s.
add_test(NAME cli_run_generalized_alpha_stops_at_track_end
  COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:flextrack>
          -DSCENE=${CMAKE_CURRENT_SOURCE_DIR}/integrators/slider_on_arc_generalized_alpha.prm
          -DOUT=${CMAKE_CURRENT_BINARY_DIR}/ga_end_of_track -DSTOP=0.642477
          "-DREGEX=at t = 0.642478 s the contact slide_on_arm1 of joint 'slide' reached the end of its track"
          -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_track_end.cmake
  WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli_run_generalized_alpha_stops_at_track_end PROPERTIES LABELS cli)
# The same with Radau IIA (issue 24, item 5): the root located on its collocation polynomial.
add_test(NAME cli_run_radau_stops_at_track_end
  COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:flextrack>
          -DSCENE=${CMAKE_CURRENT_SOURCE_DIR}/integrators/slider_on_arc_radau.prm
          -DOUT=${CMAKE_CURRENT_BINARY_DIR}/radau_end_of_track -DSTOP=0.642477
          "-DREGEX=at t = 0.642478 s the contact slide_on_arm1 of joint 'slide' reached the end of its track"
          -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_track_end.cmake
  WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli_run_radau_stops_at_track_end PROPERTIES LABELS cli)

# 'Method = auto' (issue 24, item 3): the flexible double pendulum of prm/bench/ with no Integrator
# subsection runs with Radau IIA, says so, and closes its energy balance (about 3 s).
add_test(NAME cli_run_auto_method_is_radau_for_flexible_scenes
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/integrators/check_auto_method.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR}/prm/bench/default_double_pendulum.prm ${CMAKE_CURRENT_BINARY_DIR}/cli_auto_method)
set_tests_properties(cli_run_auto_method_is_radau_for_flexible_scenes PROPERTIES LABELS cli TIMEOUT 300
  FAIL_REGULAR_EXPRESSION "FAILED")

# Issue 24, item 2: Andrews' squeezing mechanism (prm/bench/andrews_squeezer.prm, 7 rigid bars in
# a closed loop) against the published reference solution at t = 0.03 s (IVP Test Set, problem
# "andrews"): IDA at rtol 1e-4, 1e-6, 1e-8 and 1e-10 each completes, the probes' error is at most
# 300 x rtol of the mechanism's size, falls from each tolerance to the next and with a slope of at
# least 0.7 over them (tests/bench/andrews_squeezer.py says why).
add_test(NAME cli_run_andrews_squeezer_error_follows_the_tolerance
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/bench/andrews_squeezer.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR}/prm/bench/andrews_squeezer.prm ${CMAKE_CURRENT_BINARY_DIR}/cli_andrews --check)
set_tests_properties(cli_run_andrews_squeezer_error_follows_the_tolerance PROPERTIES LABELS cli TIMEOUT 600
  FAIL_REGULAR_EXPRESSION "FAIL")
# The same mechanism's work-precision, rtol 1e-3 ... 1e-10, three runs each (label bench): CPU and
# error side by side, the slope of the error over the tolerance and CPU(1e-8) / CPU(1e-5).
add_test(NAME bench_andrews_squeezer_work_precision
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/bench/andrews_squeezer.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR}/prm/bench/andrews_squeezer.prm ${CMAKE_CURRENT_BINARY_DIR}/bench_andrews)
set_tests_properties(bench_andrews_squeezer_work_precision PROPERTIES LABELS bench TIMEOUT 1800
  FAIL_REGULAR_EXPRESSION "FAIL")
