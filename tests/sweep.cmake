# flextrack sweep (issue 26): the laser robot's study run with -j 2 and under mpirun -np 2 (the
# same sweep.csv), a case against the plain run of its --set entries, a study killed and
# restarted, a failing case as a row, bad studies refused before any case runs. Label cli.
function(flextrack_sweep_check name check)
  add_test(NAME cli_sweep_${name}
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/sweep/check_sweep.py ${check} $<TARGET_FILE:flextrack> ${MPIRUN}
            ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/sweep/${name})
  set_tests_properties(cli_sweep_${name} PROPERTIES LABELS cli PROCESSORS 2)
endfunction()
flextrack_sweep_check(laser_robot_study_same_with_fork_and_mpi agree)
flextrack_sweep_check(killed_study_reruns_only_missing_cases restart)
flextrack_sweep_check(failed_case_is_a_row failed_case)
flextrack_sweep_check(bad_study_is_refused_before_any_case bad_study)
# The Python front end's example in doc/python.md, run as written (issue 26, item 4).
add_test(NAME cli_python_example_runs_as_written
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/python/run_python_example.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/sweep/python_example)
set_tests_properties(cli_python_example_runs_as_written PROPERTIES LABELS cli PROCESSORS 2)
# Benchmark (issue 26): the sweep machinery's cost per case against a loop of 'flextrack run'
# processes, and the laser robot study's wall time with 1 and 2 processes and MPI ranks
# (tests/bench/sweep_bench.py; doc/benchmarks.md, "Parameter studies").
add_test(NAME bench_sweep_machinery_and_scaling
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/bench/sweep_bench.py $<TARGET_FILE:flextrack> ${MPIRUN}
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/sweep/bench)
set_tests_properties(bench_sweep_machinery_and_scaling PROPERTIES LABELS bench PROCESSORS 2 TIMEOUT 3600 RUN_SERIAL TRUE)
# The laser robot's convergence table of doc/validation.md, reproduced by prm/laser_robot_convergence.prm
# (12 cases of the full 10 s: about 1 minute on 2 cores).
add_test(NAME bench_laser_robot_convergence_study_reproduces_table
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/bench/check_convergence_table.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/sweep/convergence)
set_tests_properties(bench_laser_robot_convergence_study_reproduces_table PROPERTIES LABELS bench PROCESSORS 2 TIMEOUT 1800)
