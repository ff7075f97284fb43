# Issue 13: the worked examples of doc/exports.md are what the exporter writes. The script
# reduces and exports each scene the document names (from the source folder, so the recorded
# scene path is the documented one) and compares every marked block with the file. Label cli.
add_test(NAME cli_mbdyn_doc_examples_match_the_exporter
  COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/python/check_mbdyn_doc_examples.py $<TARGET_FILE:flextrack>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/mbdyn_doc_examples)
set_tests_properties(cli_mbdyn_doc_examples_match_the_exporter PROPERTIES LABELS cli)
