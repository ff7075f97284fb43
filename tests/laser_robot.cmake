# Command-line tests of the laser robot's rigid reference (issue 10 item 4; Multibody/Rigid
# reference, doc/laser_robot.md): tests/laser_robot/checks.py, reference and tolerance beside each
# assertion. Both runs take the first second of prm/laser_robot.prm (tests/multibody_input/); the
# bodies are reduced into ./output/ of the working folder by the first and reused by the second.
# Label cli.
set(LASER_OUT ${CMAKE_CURRENT_BINARY_DIR}/laser_robot)
file(MAKE_DIRECTORY ${LASER_OUT})
function(flextrack_laser_robot_check name check scene)
  add_test(NAME cli_${name}
    COMMAND ${SYSTEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/laser_robot/checks.py ${check} $<TARGET_FILE:flextrack>
            ${CMAKE_CURRENT_SOURCE_DIR}/multibody_input/${scene} ${LASER_OUT}/${name}
    WORKING_DIRECTORY ${LASER_OUT})
  set_tests_properties(cli_${name} PROPERTIES LABELS cli TIMEOUT 900 RESOURCE_LOCK laser_robot_body_cache)
endfunction()
# deviation.csv (rigid positions, |r - r_rigid|) agrees with probes.csv and summary.json; the
# PNG is drawn (or a warning says why not).
flextrack_laser_robot_check(run_laser_robot_writes_deviation_from_rigid_reference deviation laser_robot_1s.prm)
# Every body rigid at rtol 1e-10: the head on the nominal path (the kinematic composition of the
# turntable angle, the sleeve's arc length on arm I and arm I's rotation-minimising frame) to 1e-10 m.
flextrack_laser_robot_check(run_laser_robot_rigid_reproduces_nominal_path nominal laser_robot_rigid_tight.prm)
# Nothing to compare: refused before the run, one line, exit 2, nothing written.
flextrack_bad_input(run_rigid_reference_without_probe
  "rigid_reference_without_probe.prm: entry 'Multibody/Rigid reference': needs a probe"
  run multibody_input/rigid_reference_without_probe.prm)
