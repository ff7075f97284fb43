# End stops on tracks (issue 10: "with a stop, the contact stays on the curve"). The closed-form
# checks are gtests (MultibodyTrack.end_stop_*: a bead bouncing on an incline, IDA and
# generalised-alpha, and a plastic stop); here the scene entries and their refusals.

# A slider released on the quarter-circle arm falls into its lower end (stop with e = 0.5), bounces
# and comes to rest there: the run reaches its end time (exit 0), the constraints hold (1e-6 m,
# the scene's tolerances; measured 9.5e-8) and the energy balance, with the impacts' losses
# counted as dissipated, closes to 1e-4 (measured 7.4e-6; without the losses it would be off by
# all 2.82 J of the drop, 18 % of the energy).
add_test(NAME cli_run_slider_bounces_on_end_stop_and_rests
  COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:flextrack> -DSCENE=${TRACK_INPUT}/slider_end_stops.prm
          -DOUT=${TRACK_OUT}/end_stops
          "-DBOUNDS=relative_energy_balance_error;1e-4;position_residual;1e-6"
          -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_summary_bounds.cmake
  WORKING_DIRECTORY ${TRACK_OUT})
set_tests_properties(cli_run_slider_bounces_on_end_stop_and_rests PROPERTIES LABELS cli)

flextrack_track_bad_input(end_stops_on_driven_contact
  "end_stops_on_driven_contact.prm: entry 'Joint slide/End of track': 'stops' needs a contact that is not motion-driven"
  end_stops_on_driven_contact.prm)
flextrack_track_bad_input(restitution_above_one
  "restitution_above_one.prm: entry 'Joint slide/Restitution': must be >= 0 and <= 1 .got 2."
  restitution_above_one.prm)
