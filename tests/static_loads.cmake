# 'flextrack static' (issue 12): pressure loads, support displacements and the fields it writes
# (VTU with stresses or section forces, section_forces.csv), checked against closed forms by
# tests/static_input/check_static_loads.py (the references and tolerances are stated there).
add_test(NAME cli_static_pressure_and_support_displacements_match_closed_forms
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/static_input/check_static_loads.py $<TARGET_FILE:flextrack>
          ${CMAKE_CURRENT_SOURCE_DIR}/static_input ${CMAKE_CURRENT_BINARY_DIR}/static_output/loads)
set_tests_properties(cli_static_pressure_and_support_displacements_match_closed_forms PROPERTIES LABELS cli TIMEOUT 600)

# Bad input (flextrack_static_input_error, tests/static.cmake).
flextrack_static_input_error(cli_bad_input_static_settlement_without_support settlement_off_support.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*settlement_off_support.prm: entry 'Load case settle/Support displacements': there is no pinned or clamped support at s = 1 m; allowed: the arc lengths \\[m\\] of the supports: 0, 2\n$")
flextrack_static_input_error(cli_bad_input_static_settlement_in_a_free_component settlement_free_component.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*settlement_free_component.prm: entry 'Load case stretch/Support displacements': the support 'x = 0' does not fix the y component, so it cannot prescribe it; allowed: 0 there\n$")
flextrack_static_input_error(cli_bad_input_static_pressure_without_faces pressure_on_an_edge.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*pressure_on_an_edge.prm: entry 'Load case push/Pressures': node set 'EDGE' holds no whole boundary face.*allowed: a set of boundary faces")
flextrack_static_input_error(cli_bad_input_static_iterative_solver_on_an_arm iterative_arm.prm
  "-DEXPECT_ERROR=^flextrack: error: [^\n]*iterative_arm.prm: entry 'Static/Linear solver': 'iterative' is for solid scenes; an arm's factor is small and exact: allowed here: 'direct'\n$")
