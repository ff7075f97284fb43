# Hostile and careless input (issue 15): label badinput, in the default run. Included from
# tests/CMakeLists.txt (the variables SYSTEM_PYTHON and the flextrack target are defined there).
add_test(NAME badinput_output_folder_cannot_run_shell_commands
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/badinput/shell_injection.sh $<TARGET_FILE:flextrack> ${CMAKE_SOURCE_DIR}
          ${CMAKE_CURRENT_BINARY_DIR}/badinput/shell_injection)
add_test(NAME badinput_hostile_reduced_body_files_are_refused
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/badinput/hostile_reduced_body.py $<TARGET_FILE:flextrack>
          ${CMAKE_CURRENT_BINARY_DIR}/exports/result/reduced_body.h5 ${CMAKE_CURRENT_BINARY_DIR}/badinput/hostile_body)
set_tests_properties(badinput_hostile_reduced_body_files_are_refused PROPERTIES
  DEPENDS cli_exports_read_by_paraview_meshio_h5py)
set_tests_properties(badinput_output_folder_cannot_run_shell_commands badinput_hostile_reduced_body_files_are_refused
  PROPERTIES LABELS badinput)
