# Fuzzing of the readers of hostile input, and reproducibility of reruns (issue 11, items 4-5;
# doc/testing.md). Included from tests/CMakeLists.txt (SYSTEM_PYTHON, MPIRUN and the flextrack
# target are defined there).

# The mutation driver (tests/fuzz/fuzz_readers.cc): seeded mutants of seed files, each read in a
# forked copy of the driver by the same reader code the command line runs.
file(GLOB FUZZ_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/*.cc)
add_executable(fuzz_readers ${FUZZ_SOURCES})
target_link_libraries(fuzz_readers flextrack_lib)
deal_ii_setup_target(fuzz_readers)
target_precompile_headers(fuzz_readers REUSE_FROM flextrack_lib)

set(FUZZ_WORK ${CMAKE_CURRENT_BINARY_DIR}/fuzz)
file(MAKE_DIRECTORY ${FUZZ_WORK})
# A valid reduced body to mutate: a small body (2 x 2 x 2 hex20 cells and a curved arm, so the
# file has interfaces, output points, an arm with its geometry text), reduced in well under 1 s.
add_test(NAME fuzz_seed_reduced_body
  COMMAND $<TARGET_FILE:flextrack> reduce ${CMAKE_CURRENT_SOURCE_DIR}/input/small_body.prm -o ${FUZZ_WORK}/seed_body)
set_tests_properties(fuzz_seed_reduced_body PROPERTIES LABELS fuzz FIXTURES_SETUP fuzz_body_seed)

# One bounded run per reader: 20 s of mutants in Release. The Debug + sanitizer build sets
# FLEXTRACK_TIME_LIMIT_FACTOR=8: the driver divides the budget by it (2.5 s of mutants, about
# 10-25 s of wall time with the seeds themselves) and multiplies the 10 s per-input limit by it.
# --seed fixes the sequence of mutants (the same inputs on every run, up to where time ends it).
set(FUZZ_SECONDS 20)
set(FUZZ_SEEDS_scene ${CMAKE_CURRENT_SOURCE_DIR}/input ${CMAKE_SOURCE_DIR}/prm ${CMAKE_CURRENT_SOURCE_DIR}/multibody_input
                     ${CMAKE_CURRENT_SOURCE_DIR}/track_input)
set(FUZZ_SEEDS_inp ${CMAKE_SOURCE_DIR}/meshes ${CMAKE_CURRENT_SOURCE_DIR}/input ${CMAKE_CURRENT_SOURCE_DIR}/input/hostile_meshes)
set(FUZZ_SEEDS_msh ${FUZZ_SEEDS_inp})
set(FUZZ_SEEDS_body ${FUZZ_WORK}/seed_body/reduced_body.h5 ${CMAKE_CURRENT_SOURCE_DIR}/input/foreign.h5
                    ${CMAKE_CURRENT_SOURCE_DIR}/input/not_hdf5.h5)
foreach(target scene inp msh body)
  file(MAKE_DIRECTORY ${FUZZ_WORK}/${target})
  add_test(NAME fuzz_${target}_reader_survives_mutants
    COMMAND fuzz_readers ${target} ${FUZZ_SEEDS_${target}} --seconds ${FUZZ_SECONDS} --seed 11 --work ${FUZZ_WORK}/${target}
    # An empty folder: a multibody scene finds no cached reduced body here (it is skipped
    # instead of reduced), and nothing a reader might write lands in the source tree.
    WORKING_DIRECTORY ${FUZZ_WORK}/${target})
  set_tests_properties(fuzz_${target}_reader_survives_mutants PROPERTIES LABELS fuzz TIMEOUT 600)
endforeach()
set_tests_properties(fuzz_body_reader_survives_mutants PROPERTIES FIXTURES_REQUIRED fuzz_body_seed)

# Every input a fuzz run ever found crashing (tests/fuzz/regressions/), read again unmodified.
add_test(NAME fuzz_regression_inputs_are_refused_cleanly
  COMMAND fuzz_readers --replay ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/regressions --work ${FUZZ_WORK}/replay
  WORKING_DIRECTORY ${FUZZ_WORK})
set_tests_properties(fuzz_regression_inputs_are_refused_cleanly PROPERTIES LABELS fuzz)

# Reproducibility (issue 11, item 4): the same run twice gives bitwise the same CSV files and
# HDF5 datasets (a rigid mechanism, a flexible body reduced afresh, a reduction alone), about
# 10 s. Runs under mpirun are compared with serial ones instead (same to round-off, not bitwise:
# another factorisation): the partitioned solid by cli_solid_under_mpi_matches_serial, the
# distributed reduction by cli_reduce_under_mpi_matches_serial_* (tests/mpi/).
add_test(NAME stress_reruns_are_bitwise_identical
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/expect_identical_reruns.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/reruns)
set_tests_properties(stress_reruns_are_bitwise_identical PROPERTIES LABELS stress TIMEOUT 600)
