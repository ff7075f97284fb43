# Every numeric entry of print-parameters fed nan, inf, -1, 0 and 1e300 (issue 15, acceptance:
# the property test). Included from tests/CMakeLists.txt (SYSTEM_PYTHON and the flextrack target
# are defined there).
# Default run (label badinput, about 250 runs, under 3 minutes with 2 processes): a deterministic
# subset, every entry once in the first scene that reads it; nan and inf only where no deal.II
# Double/Integer pattern refuses them already (see numeric_entries.py).
add_test(NAME badinput_numeric_entries_run_validly_or_are_refused
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/badinput/numeric_entries.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/badinput/numeric_entries --jobs 2)
set_tests_properties(badinput_numeric_entries_run_validly_or_are_refused PROPERTIES
  LABELS badinput PROCESSORS 2 TIMEOUT 1500)
# The full sweep (label stress, about 630 runs, about 7 minutes): every entry in every scene that
# reads it, all five values. Not in the default run: it exists only in the configuration
# "stress", run it with `ctest -C stress -L stress`.
add_test(NAME stress_numeric_entries_full_sweep CONFIGURATIONS stress
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/badinput/numeric_entries.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/badinput/numeric_entries_full --full --jobs 2)
set_tests_properties(stress_numeric_entries_full_sweep PROPERTIES LABELS stress PROCESSORS 2 TIMEOUT 1800)
