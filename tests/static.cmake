# 'flextrack static' (issue 12): an arm scene's load cases solved on the full FE model. Included
# from tests/CMakeLists.txt (the flextrack target is defined there).
function(flextrack_static_test name prm)
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:flextrack> -DPRM=${CMAKE_CURRENT_SOURCE_DIR}/input/${prm}
            -DOUT=${CMAKE_CURRENT_BINARY_DIR}/static_output/${name} ${ARGN}
            -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_static.cmake)
endfunction()

# Straight cantilever L = 3 m, circle d = 0.01 m, steel, tip force 1 N: Timoshenko closed form
# d = P L^3 / (3 EI) + P L / (k G A) = 0.08730838804 m (k = 6 (1 + nu) / (7 + 6 nu), Cowper), exact
# for cubic elements up to the conditioning of this slender arm (L/d = 300, cond(K) about 1e12):
# the printed tip displacement must show 9 digits (measured 0.08730838808 m, 4.6e-10; the
# solver's refinement makes u consistent with the assembled K, not closer to the closed form);
# the reactions balance the load to the round-off of K u: printed |F + R| below 1e-8 N
# (measured 8.6e-10 N).
flextrack_static_test(cli_static_cantilever_matches_closed_form static_cantilever.prm
  "-DEXPECT_OUTPUT_1=s = 3 m:  u = \\([^,]*, -0.0873083880[0-9]*, [^)]*\\) m"
  "-DEXPECT_OUTPUT_2=equilibrium: +\\|F \\+ R\\| = ([0-9.]+e-(09|1[0-9]|[2-9][0-9])|0.00e\\+00) N")
set_tests_properties(cli_static_cantilever_matches_closed_form PROPERTIES LABELS cli)

# Bad input: one line naming the file, the entry and what is allowed; exit 2; nothing written.
flextrack_static_test(cli_bad_input_static_load_beyond_arm static_load_beyond_arm.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*static_load_beyond_arm.prm: entry 'Load case tip/Point forces': point force at s = 3.5 m lies beyond the arm \\(its length is L = 3 m\\); allowed: 0 <= s <= L\n$")
flextrack_static_test(cli_bad_input_static_nonfinite_load static_nonfinite_load.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*static_nonfinite_load.prm: entry 'Load case tip/Point forces': 'nan' is not a finite number \\(a component \\[N\\]\\)\n$")
flextrack_static_test(cli_bad_input_static_nonfinite_gravity static_nonfinite_gravity.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*static_nonfinite_gravity.prm: entry 'Load case weight/Gravity': 'inf' is not a finite number")
flextrack_static_test(cli_bad_input_static_reversed_line_load static_reversed_line_load.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*static_reversed_line_load.prm: entry 'Load case weight/Line loads': .*allowed: S0 < S1\n$")
set_tests_properties(cli_bad_input_static_load_beyond_arm cli_bad_input_static_nonfinite_load
  cli_bad_input_static_nonfinite_gravity cli_bad_input_static_reversed_line_load PROPERTIES LABELS "cli;badinput")
flextrack_static_test(cli_bad_input_static_unknown_node_set static_unknown_node_set.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*static_unknown_node_set.prm: entry 'Load case extension/Node set forces': node set 'TIP' does not exist in box [^\n]*; allowed: XMAX, XMIN, YMAX, YMIN, ZMAX, ZMIN\n$")
set_tests_properties(cli_bad_input_static_unknown_node_set PROPERTIES LABELS "cli;badinput")

# Body scenes: every load case solved with the full FE model and the reduced body (issue 12 item 3).
function(flextrack_body_static_test name prm)
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:flextrack> -DPRM=${CMAKE_CURRENT_SOURCE_DIR}/static_input/${prm}
            -DOUT=${CMAKE_CURRENT_BINARY_DIR}/static_output/${name} ${ARGN}
            -P ${CMAKE_CURRENT_SOURCE_DIR}/static_input/expect_body_static.cmake)
  set_tests_properties(${name} PROPERTIES LABELS cli)
endfunction()
# Quarter ring with track load modes (default reduction: 20 normal modes, 8 stations), point
# loads between stations at 0.37 L and 0.61 L and gravity, reported at the two load points (2 x 3
# differences): within 1e-4, the accuracy ReducedBody.track_load_modes_represent_loads_between_stations
# shows for the same body and loads (1.2e-5; measured here 8.0e-6, 1.2e-5 and 1.2e-7..1.8e-7).
flextrack_body_static_test(cli_static_body_loads_between_track_stations body_ring_between_stations.prm
  -DCOUNT=6 -DMAX_DIFFERENCE=1e-4)
# Craig-Bampton body, force and moment at its interface: exact up to round-off (bound 1e-8, as
# ReducedBody.craig_bampton_of_an_arm_clamped_in_a_block; measured 1.9e-11).
flextrack_body_static_test(cli_static_body_craig_bampton_interface_exact body_bracket_interface.prm
  -DCOUNT=1 -DMAX_DIFFERENCE=1e-8)
# Bad input in scenes of tests/static_input (body scenes here, more in static_loads.cmake): one
# line naming the file, the entry and what is allowed; exit 2; nothing written.
function(flextrack_static_input_error name prm)
  add_test(NAME ${name}
    COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:flextrack> -DPRM=${CMAKE_CURRENT_SOURCE_DIR}/static_input/${prm}
            -DOUT=${CMAKE_CURRENT_BINARY_DIR}/static_output/${name} ${ARGN}
            -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_static.cmake)
  set_tests_properties(${name} PROPERTIES LABELS "cli;badinput")
endfunction()
flextrack_static_input_error(cli_bad_input_static_body_load_beyond_arm body_load_beyond_arm.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*body_load_beyond_arm.prm: entry 'Load case tip/Point forces': point force on arm 'ring' at s = 2 m lies beyond the arm \\(its length is L = 1.5708 m\\); allowed: 0 <= s <= L\n$")
flextrack_static_input_error(cli_bad_input_static_body_unknown_arm body_unknown_arm.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*body_unknown_arm.prm: entry 'Load case tip/Point forces': 'boom' is not an arm of the body; allowed: ring\n$")
