# Command-line tests of 'flextrack run' and 'flextrack linearize' (issue 9): numbers against
# closed forms (tests/multibody_cli/checks.py: reference and tolerance beside each assertion),
# eight runs started at once, a solver failure that keeps its results, and bad input that names
# the file, the entry and the allowed names and writes nothing. Label cli.
set(MB_OUT ${CMAKE_CURRENT_BINARY_DIR}/multibody_cli)
file(MAKE_DIRECTORY ${MB_OUT})

function(flextrack_multibody_check name check scene)
  add_test(NAME cli_${name}
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/multibody_cli/checks.py ${check} $<TARGET_FILE:flextrack>
            ${scene} ${MB_OUT}/${name}
    WORKING_DIRECTORY ${MB_OUT}) # a flexible body's reduced-body cache goes to ./output/
  set_tests_properties(cli_${name} PROPERTIES LABELS cli)
endfunction()
flextrack_multibody_check(run_pendulum_period_matches_elliptic_integral pendulum ${CMAKE_SOURCE_DIR}/prm/pendulum.prm)
flextrack_multibody_check(run_slider_crank_follows_closed_form slider_crank ${CMAKE_SOURCE_DIR}/prm/slider_crank.prm)
flextrack_multibody_check(run_flexible_pendulum_balances_energy flexible ${CMAKE_SOURCE_DIR}/prm/flexible_pendulum.prm)
flextrack_multibody_check(linearize_pendulum_frequency_matches_closed_form linearize
                          ${CMAKE_CURRENT_SOURCE_DIR}/multibody_input/pendulum_at_rest.prm)
flextrack_multibody_check(run_solver_failure_keeps_rows_and_says_what_to_change solver_failure
                          ${CMAKE_CURRENT_SOURCE_DIR}/multibody_input/locking_slider_crank.prm)
flextrack_multibody_check(run_spin_up_without_geometric_stiffening_stops_as_unstable unstable_spin_up
                          ${CMAKE_SOURCE_DIR}/prm/bench/spin_up_beam.prm)
flextrack_multibody_check(run_chain_of_one_body_scene_shares_its_reduced_body shared_reduced_body
                          ${CMAKE_SOURCE_DIR}/prm/cantilever_body.prm)
flextrack_multibody_check(run_progress_reaches_a_pipe_line_by_line progress_line_by_line
                          ${CMAKE_SOURCE_DIR}/prm/slider_crank.prm)
flextrack_multibody_check(run_interrupted_by_a_signal_writes_its_rows interrupted_run_writes_its_rows
                          ${CMAKE_SOURCE_DIR}/prm/slider_crank.prm)
flextrack_multibody_check(run_results_h5_is_written_as_the_run_goes results_written_as_run_goes
                          ${CMAKE_SOURCE_DIR}/prm/pendulum.prm)
flextrack_multibody_check(run_set_on_command_line_equals_the_edited_files set_on_command_line
                          ${CMAKE_SOURCE_DIR}/prm/cantilever_body.prm)
flextrack_multibody_check(run_slider_off_its_track_is_said slider_off_its_track_is_said
                          ${CMAKE_CURRENT_SOURCE_DIR}/track_input/slider_on_arc.prm)
flextrack_multibody_check(run_contact_on_arm_without_track_modes_is_said contact_without_track_modes_is_said
                          ${CMAKE_SOURCE_DIR}/prm/slider_on_helix.prm)
flextrack_multibody_check(run_end_stop_on_flexible_arm_with_generalized_alpha end_stop_on_flexible_arm_with_generalized_alpha
                          ${CMAKE_CURRENT_SOURCE_DIR}/track_input/slider_end_stops.prm)
flextrack_multibody_check(run_end_stop_on_flexible_arm_with_radau end_stop_on_flexible_arm_with_radau
                          ${CMAKE_CURRENT_SOURCE_DIR}/track_input/slider_end_stops.prm)
flextrack_multibody_check(run_passage_timed_to_the_end_time_completes passage_ends_at_end_time
                          ${CMAKE_CURRENT_SOURCE_DIR}/track_input/slider_on_arc.prm)
flextrack_multibody_check(run_energy_balance_of_a_run_starting_at_rest run_energy_balance_starting_at_rest
                          ${CMAKE_SOURCE_DIR}/prm/bench/slewing_beam.prm)
flextrack_multibody_check(run_energy_balance_stays_small_at_turning_points energy_balance_at_turning_points
                          ${CMAKE_SOURCE_DIR}/prm/pendulum.prm)
flextrack_multibody_check(run_parameters_used_reruns_from_another_folder parameters_used_reruns
                          ${CMAKE_CURRENT_SOURCE_DIR}/track_input/slider_on_arc.prm)
flextrack_multibody_check(linearize_neutral_slider_is_not_called_unstable linearize_neutral_slider
                          ${CMAKE_SOURCE_DIR}/prm/bench/default_slider_on_turning_arm.prm)
flextrack_multibody_check(reduce_arm_body_without_solid_line_has_no_solid arm_body_without_solid_line
                          ${CMAKE_SOURCE_DIR}/prm/cantilever_body.prm)
flextrack_multibody_check(run_step_limiter_is_the_fast_pendulum step_limiter_is_the_fast_pendulum
                          ${CMAKE_CURRENT_SOURCE_DIR}/multibody_input/fast_and_slow_pendulums.prm)
flextrack_multibody_check(run_json_scene_reads_like_prm json_like_prm ${CMAKE_CURRENT_SOURCE_DIR}/multibody_input/pendulum_1s.json)
set_tests_properties(cli_run_flexible_pendulum_balances_energy PROPERTIES TIMEOUT 600)
# Multibody/Initial state = static equilibrium: a cantilever sagging under its weight.
flextrack_multibody_check(run_sagging_cantilever_starts_from_static_equilibrium equilibrium
                          ${CMAKE_SOURCE_DIR}/prm/sagging_cantilever.prm)
set_tests_properties(cli_run_sagging_cantilever_starts_from_static_equilibrium PROPERTIES TIMEOUT 600)

# One stability verdict for the static equilibrium of 'run' and for 'linearize'; a pendulum
# started horizontal is not a mechanism; linearising about a state that is not an equilibrium is
# said (issue 25, items 3 and 4). tests/multibody_cli/equilibrium_checks.py: closed forms and
# tolerances beside each assertion.
function(flextrack_equilibrium_check name check scene)
  add_test(NAME cli_${name}
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/multibody_cli/equilibrium_checks.py ${check}
            $<TARGET_FILE:flextrack> ${scene} ${MB_OUT}/${name}
    WORKING_DIRECTORY ${MB_OUT})
  set_tests_properties(cli_${name} PROPERTIES LABELS cli)
endfunction()
flextrack_equilibrium_check(run_inverted_pendulum_equilibrium_is_unstable_at_closed_form_rate inverted_pendulum
                            ${CMAKE_CURRENT_SOURCE_DIR}/multibody_cli/inverted_pendulum_equilibrium.prm)
flextrack_equilibrium_check(run_double_pendulum_from_horizontal_hangs_down double_pendulum_from_horizontal
                            ${CMAKE_CURRENT_SOURCE_DIR}/multibody_cli/double_pendulum_horizontal.prm)
flextrack_equilibrium_check(linearize_off_equilibrium_says_so linearize_off_equilibrium
                            ${CMAKE_CURRENT_SOURCE_DIR}/multibody_cli/pendulum_at_30_degrees.prm)

add_test(NAME cli_run_eight_processes_at_once
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/multibody_cli/eight_at_once.sh $<TARGET_FILE:flextrack> run
          ${CMAKE_CURRENT_SOURCE_DIR}/multibody_input/pendulum_1s.prm ${MB_OUT}/eight_at_once)
# The same for a command that starts MPI (each singleton keeps its session files in a folder of
# its own, src/app/main.cc).
add_test(NAME cli_modes_eight_processes_at_once
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/multibody_cli/eight_at_once.sh $<TARGET_FILE:flextrack> modes
          ${CMAKE_CURRENT_SOURCE_DIR}/input/straight_cantilever.prm ${MB_OUT}/eight_modes_at_once)
set_tests_properties(cli_run_eight_processes_at_once cli_modes_eight_processes_at_once PROPERTIES LABELS cli)

# Bad input: exit status 2, one line naming the file, the entry and what is allowed, no output.
flextrack_bad_input(run_joint_names_unknown_body
  "unknown_body.prm: entry 'Joint pivot/Body 1': there is no body 'bobb'; allowed: ground, bob" run multibody_input/unknown_body.prm)
flextrack_bad_input(run_joint_asks_interface_of_rigid_body
  "interface_on_rigid_body.prm: entry 'Joint pivot/Interface 1': body 'bob' is not flexible; it has no interface 'tip'"
  run multibody_input/interface_on_rigid_body.prm)
flextrack_bad_input(run_probe_frame_unknown_body
  "unknown_probe_frame.prm: entry 'Probe bob_centre/Frame': there is no body 'hub'; allowed: ground, bob"
  run multibody_input/unknown_probe_frame.prm)
flextrack_bad_input(run_ground_listed_as_body "ground_listed.prm: entry 'Multibody/Bodies': 'ground' is the fixed frame"
  run multibody_input/ground_listed.prm)
flextrack_bad_input(run_flexible_body_without_source
  "flexible_without_source.prm: entry 'Body bob/Body scene': a flexible body needs exactly one of"
  run multibody_input/flexible_without_source.prm)
flextrack_bad_input(run_missing_body_scene
  "missing_body_scene.prm: entry 'Body bob/Body scene': .*no_such_body.prm: cannot open the parameter file: no such file"
  run multibody_input/missing_body_scene.prm)
flextrack_bad_input(run_static_equilibrium_of_a_mechanism
  "level_slider_equilibrium.prm: entry 'Multibody/Initial state': 'static equilibrium': the scene is a mechanism under these loads.*along 'body slider, R'_x'"
  run multibody_input/level_slider_equilibrium.prm)
flextrack_bad_input(linearize_needs_multibody_scene "entry 'Model': is 'arm'; 'flextrack run' and 'flextrack linearize' need 'Model = multibody'"
  linearize input/straight_cantilever.prm)

# The curved boom reduced once into ./output/curved_boom_body/ (0.3 s), for the tests below that read
# its reduced_body.h5. A fixture, not a dependency on the flexible-pendulum run: that run is left
# out of the Debug + sanitizer subset (tests/long_tests.txt), and a DEPENDS on a test that is not
# run does not make it run.
add_test(NAME cli_reduce_curved_boom_body_for_the_multibody_tests
  COMMAND $<TARGET_FILE:flextrack> reduce ${CMAKE_SOURCE_DIR}/prm/curved_boom_body.prm
  WORKING_DIRECTORY ${MB_OUT})
set_tests_properties(cli_reduce_curved_boom_body_for_the_multibody_tests PROPERTIES LABELS cli
  FIXTURES_SETUP curved_boom_reduced)

# A joint naming an interface the flexible body does not have: the allowed interfaces are listed.
# The scene uses the reduced body of the fixture above.
file(WRITE ${MB_OUT}/unknown_interface.prm
  "set Model = multibody\nsubsection Multibody\n  set Bodies = boom\n  set Joints = pivot\nend\n"
  "subsection Body boom\n  set Kind = flexible\n"
  "  set Reduced body file = ${MB_OUT}/output/curved_boom_body/reduced_body.h5\nend\n"
  "subsection Joint pivot\n  set Body 1 = boom\n  set Interface 1 = tipp\nend\n")
flextrack_bad_input(run_joint_names_unknown_interface
  "unknown_interface.prm: entry 'Joint pivot/Interface 1': body 'boom' has no interface or output point 'tipp'; allowed: tip"
  run ${MB_OUT}/unknown_interface.prm)
set_tests_properties(cli_bad_input_run_joint_names_unknown_interface PROPERTIES FIXTURES_REQUIRED curved_boom_reduced)

# A flexible body from a reduced body file (.h5) runs like the same body from its body scene.
file(WRITE ${MB_OUT}/flexible_from_h5.prm
  "include ${CMAKE_SOURCE_DIR}/prm/flexible_pendulum.prm\nsubsection Body boom\n  set Body scene =\n"
  "  set Reduced body file = ${MB_OUT}/output/curved_boom_body/reduced_body.h5\nend\n")
flextrack_multibody_check(run_flexible_from_reduced_body_file_matches_body_scene same_as_flexible ${MB_OUT}/flexible_from_h5.prm)
set_tests_properties(cli_run_flexible_from_reduced_body_file_matches_body_scene PROPERTIES
  FIXTURES_REQUIRED curved_boom_reduced DEPENDS cli_run_flexible_pendulum_balances_energy TIMEOUT 600) # compares with its probes.csv

# The same curved boom (prm/flexible_pendulum.prm, from the fixture's reduced body) started near
# upside down with 'Initial state = static equilibrium': Newton converges to the inverted
# equilibrium, which the old stiffness test called stable (its bound scaled with the stiff modes).
file(WRITE ${MB_OUT}/inverted_flexible_link.prm
  "include ${CMAKE_SOURCE_DIR}/prm/flexible_pendulum.prm\nsubsection Multibody\n  set Initial state = static equilibrium\nend\n"
  "subsection Body boom\n  set Body scene =\n"
  "  set Reduced body file = ${MB_OUT}/output/curved_boom_body/reduced_body.h5\n"
  "  set Rotation vector = 0, 0, 0.3\n  set Position = -0.047766824456280305, -0.014776010333066978, -0.05\nend\n")
flextrack_equilibrium_check(run_inverted_flexible_link_equilibrium_is_unstable inverted_flexible_link
                            ${MB_OUT}/inverted_flexible_link.prm)
set_tests_properties(cli_run_inverted_flexible_link_equilibrium_is_unstable PROPERTIES FIXTURES_REQUIRED curved_boom_reduced)

# doc/tutorial.md run as written (issue 25, item 15): every file and command of it; the benchmark
# step on its own, under the bench label.
add_test(NAME cli_tutorial_runs_as_written
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/tutorial/run_tutorial.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR}/doc/tutorial.md ${MB_OUT}/tutorial --no-bench)
set_tests_properties(cli_tutorial_runs_as_written PROPERTIES LABELS cli TIMEOUT 900)
add_test(NAME bench_tutorial_benchmark_runs
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/tutorial/run_tutorial.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR}/doc/tutorial.md ${MB_OUT}/tutorial_bench --bench-only)
set_tests_properties(bench_tutorial_benchmark_runs PROPERTIES LABELS bench TIMEOUT 1800)
