# Hostile and careless input (issue 15): label badinput, in the default run. Included from
# tests/CMakeLists.txt (the variables SYSTEM_PYTHON and the flextrack target are defined there).
add_test(NAME badinput_output_folder_cannot_run_shell_commands
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/badinput/shell_injection.sh $<TARGET_FILE:flextrack> ${CMAKE_SOURCE_DIR}
          ${CMAKE_CURRENT_BINARY_DIR}/badinput/shell_injection)
add_test(NAME badinput_hostile_reduced_body_files_are_refused
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/badinput/hostile_reduced_body.py $<TARGET_FILE:flextrack>
          ${CMAKE_CURRENT_BINARY_DIR}/multibody_cli/output/curved_boom_body/reduced_body.h5
          ${CMAKE_CURRENT_BINARY_DIR}/badinput/hostile_body)
# The valid body to mutate comes from the fixture curved_boom_reduced (tests/multibody_cli.cmake).
set_tests_properties(badinput_hostile_reduced_body_files_are_refused PROPERTIES
  FIXTURES_REQUIRED curved_boom_reduced)
set_tests_properties(badinput_output_folder_cannot_run_shell_commands badinput_hostile_reduced_body_files_are_refused
  PROPERTIES LABELS badinput)

# Hostile and careless scenes and command lines (issue 15, items 4-9): one test per case of
# badinput/hostile_scenes.py (nesting, resource bombs, silent nonsense, messages, write errors,
# reduce under mpirun). Each refused case must exit 2 within 5 s with one printable line naming
# the file and the entry, and leave nothing in the output folder.
set(FLEXTRACK_HOSTILE_SCENE_CASES
  expression_100000_nested_parentheses expression_nested_4000_deep expression_sum_of_200000_terms
  expression_100000_unary_minus expression_3000_unary_minus expression_power_tower_50000
  expression_power_tower_300 expression_sum_of_3000_terms_is_read scene_includes_itself json_nested_100000_deep
  arm_2147483647_elements box_2147483647_cells spline_of_200000_points converge_12_refinements_of_a_box
  converge_12_refinements_of_an_arm helix_of_1e9_turns mesh_with_a_loose_part tan_across_its_pole shift_nan shift_1e300
  line_end_at_1e308 scene_is_binary scene_is_utf16 value_of_50_mb value_of_1_mb scene_is_a_directory
  scene_is_dev_zero frequencies_csv_links_to_dev_full write_error_file_size_limit reduce_write_error_file_size_limit stale_mode_shapes_removed
  cached_body_with_nan_stiffness_is_rebuilt cached_body_with_20_flipped_bits_is_rebuilt
  cached_body_of_negative_mass_with_matching_checksum_is_rebuilt multibody_run_rebuilds_a_damaged_cached_body
  track_stations_2147483647
  mpirun_reduce mpirun_reduce_unwritable_output mpirun_run_multibody)
find_program(MPIRUN mpirun)
foreach(case ${FLEXTRACK_HOSTILE_SCENE_CASES})
  add_test(NAME badinput_scene_${case}
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/badinput/hostile_scenes.py $<TARGET_FILE:flextrack>
            ${CMAKE_CURRENT_BINARY_DIR}/badinput/hostile_scenes ${case} ${MPIRUN})
  set_tests_properties(badinput_scene_${case} PROPERTIES LABELS badinput TIMEOUT 120)
endforeach()
set_tests_properties(badinput_scene_mpirun_reduce badinput_scene_mpirun_reduce_unwritable_output
  badinput_scene_mpirun_run_multibody PROPERTIES PROCESSORS 2)

# Multibody scenes that start at a singular configuration (issue 23, item 2): a slider-crank at a
# dead point of its turned guide and a four-bar with its links in line are refused by run and
# linearize (exit 2, the joints of the loop named); genuinely redundant planar loops (a four-bar
# and prm/slider_crank.prm) still run with every joint equation, the dropped ones included, held.
foreach(case dead_point_slider_crank_run_refused dead_point_slider_crank_linearize_refused
        collinear_four_bar_run_refused collinear_four_bar_linearize_refused
        redundant_planar_four_bar_runs redundant_slider_crank_runs)
  add_test(NAME badinput_singular_start_${case}
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/badinput/singular_starts.py $<TARGET_FILE:flextrack>
            ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/badinput/singular_starts ${case})
  set_tests_properties(badinput_singular_start_${case} PROPERTIES LABELS badinput)
endforeach()
