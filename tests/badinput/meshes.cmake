# Hostile and careless mesh files (issue 15): label badinput. Included from tests/CMakeLists.txt.
# Each test runs one case of badinput/hostile_meshes.py: a solid scene whose mesh file is one of
# input/hostile_meshes/ (or a directory, /dev/zero, a link to it); `flextrack modes` must refuse
# it with exit status 2 and one short printable line naming the file, the line and the fault,
# write nothing and finish within 5 s. valid_meshes_are_read: the meshes they were made from.
set(FLEXTRACK_HOSTILE_MESH_CASES
  valid_meshes_are_read
  nset_generate_step_zero nset_generate_negative_step nset_generate_huge_end
  nset_generate_ranges_multiply gmsh_physical_tags_multiply
  gmsh_node_block_of_2_to_the_62 gmsh_node_block_of_minus_5
  gmsh_element_with_minus_1_tags gmsh_element_with_2e9_tags
  gmsh_element_block_of_2e9 gmsh_element_block_of_minus_1 gmsh_entity_with_2e9_physical_tags
  duplicate_element_id_inp duplicate_element_id_msh coincident_elements collapsed_element nset_names_missing_node
  duplicate_node_id_inp duplicate_node_id_msh
  coordinate_nan_inp coordinate_inf_inp coordinate_1e300_inp coordinate_1e308_inp coordinate_nan_msh
  mesh_file_is_a_directory mesh_file_is_dev_zero mesh_file_links_to_dev_zero
  mesh_file_over_1_gib line_of_2_mib
  binary_bytes_in_element_lines gzip_compressed_gmsh_file
  utf16_abaqus_file_with_byte_order_mark utf16_gmsh_file)
foreach(case ${FLEXTRACK_HOSTILE_MESH_CASES})
  add_test(NAME badinput_mesh_${case}
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/badinput/hostile_meshes.py $<TARGET_FILE:flextrack>
            ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/badinput/hostile_meshes ${case})
  set_tests_properties(badinput_mesh_${case} PROPERTIES LABELS badinput TIMEOUT 60)
endforeach()
