# Hostile input, round two (issue 23): the multibody commands. One test per case of
# badinput/hostile_multibody.py (the gnuplot injections through bench, laws of time that are not
# finite or have poles, tolerances and steps at 1e-300, a spring at one point, bench on probes
# that do not move). Included from tests/CMakeLists.txt (SYSTEM_PYTHON is defined there).
set(FLEXTRACK_HOSTILE_MULTIBODY_CASES
  bench_scene_name_ends_gnuplot_string bench_scene_name_with_newline_and_bang bench_relative_tolerance_zero
  bench_only_probe_on_the_ground driver_log_t driver_sqrt_of_minus_1 driver_pole_on_the_grid
  driver_pole_between_grid_points driver_exp_1000_t driver_1e308_t_squared force_1e308 torque_nan_before_1_s
  spring_with_coincident_points absolute_tolerance_1e-300 generalized_alpha_adaptive_step_1e-300 driver_smooth_runs
  rerun_removes_previous_runs_files linearize_writes_to_its_folder body_listed_without_subsection
  reference_axis_parallel_to_axis empty_scene_file ten_million_output_rows
  results_beyond_file_size_limit angular_velocity_1e6 json_scene_with_plain_keys_runs
  modes_write_error_in_mode_shapes bodies_200000_names
  arm_with_a_cusp arm_crossing_itself arm_full_ring_is_read arm_tight_helix_is_read
  arm_200_turns_crossing_itself arm_many_turns_with_a_cusp arm_200_turn_helix_is_read
  maximum_order_seven velocity_tolerance_word
  set_misspelt_entry set_misspelt_subsection set_value_outside_pattern set_unknown_body_scope set_rigid_body_scope
  set_without_equals set_value_with_a_line_break file_misspelt_entry file_misspelt_subsection file_selection_misspelt
  chain_of_150_bodies_names_every_column)
foreach(case ${FLEXTRACK_HOSTILE_MULTIBODY_CASES})
  add_test(NAME badinput_multibody_${case}
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/badinput/hostile_multibody.py $<TARGET_FILE:flextrack>
            ${CMAKE_CURRENT_BINARY_DIR}/badinput/hostile_multibody ${case})
  set_tests_properties(badinput_multibody_${case} PROPERTIES LABELS badinput TIMEOUT 300)
endforeach()
