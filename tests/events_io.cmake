# The events scheme (--collisions events) from files, the command line and
# the viewer (included by tests/CMakeLists.txt, whose carom_cli_test, run,
# data and out it uses, after io_tests.cmake and viewer_tests.cmake).

# Substeps mean nothing to it: refused, naming what asked for them.
set(events_run "${run}|--collisions|events")
carom_cli_test(events_max_travel fail
               "--max-travel 0.5 splits steps into substeps, but the events scheme has no steps to split .*: leave it out, or use --collisions pairwise"
               "${events_run}|--max-travel|0.5")
carom_cli_test(events_dt_auto fail "--dt auto splits steps into substeps, but the events scheme has no steps to split"
               "${events_run}|--dt|auto")
carom_cli_test(events_scene_max_travel fail
               "the scene file '.*events_substeps.toml' \\(max_travel or dt = \"auto\"\\) splits steps into substeps"
               "run|--backend|cpu|--scene|${data}/events_substeps.toml|--steps|5|--output-state|${out}")
carom_cli_test(events_scene_max_travel_overridden pass "\"scheme\": \"events\""
               "run|--backend|cpu|--scene|${data}/events_substeps.toml|--max-travel|0|--steps|5|--json")
carom_cli_test(events_json pass
               "\"events\": {[^}]*\"cell_crossings\": [1-9][0-9]*,[^}]*\"collisions\": [1-9][0-9]*,.*\"scheme\": \"events\""
               "run|--backend|cpu|--particles|200|--packing|0.5|--steps|20|--collisions|events|--json")
# It runs on the CPU, which is its default backend; OpenCL asked for without
# --backend (--pipeline, --device) is refused as --backend opencl is (cli.events_on_opencl).
carom_cli_test(events_default_backend pass "\"backend\": \"cpu\",.*\"scheme\": \"events\""
               "run|--particles|100|--steps|5|--collisions|events|--json")
if(OpenCL_FOUND)
    carom_cli_test(events_resident_pipeline fail
                   "--collisions events runs on the CPU only \\(one thread, double precision\\): use --backend cpu"
                   "run|--pipeline|resident|--steps|5|--output-state|${out}|--collisions|events")
endif()

# Checkpoints, resumed runs and the summary (outputs_test.py).
if(Python3_Interpreter_FOUND)
    foreach(test IN ITEMS events_checkpoint_layout events_resume_continues_bit_for_bit events_json_and_summary
                          events_resume_refusals)
        add_test(NAME outputs.${test}
                 COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/outputs_test.py --carom $<TARGET_FILE:carom>
                         --work ${CMAKE_CURRENT_BINARY_DIR}/outputs --backends ${backends} ${test})
    endforeach()
endif()

# The viewer runs the events scheme (under gravity, where parabolic flights
# and wall bounces matter): the headless line names the scheme, and the
# total energy of the engine's double state drifts by less than 1e-12.
if(CAROM_HAVE_VIEWER)
    add_test(NAME view.events_gravity
             COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DOUT_DIR=${CMAKE_CURRENT_BINARY_DIR}/view/events
                     "-DARGS=view|--backend|cpu|--particles|300|--gravity|0|-1|--collisions|events|--window|400|300|--frames|20"
                     "-DOUTPUT_REGEX=20 frames of 300 disks, events collisions, total energy drift ([+-]0|[+-][0-9.]+e-(1[2-9]|[2-9][0-9]|[1-9][0-9][0-9])) over 0.8 time units"
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/run_viewer.cmake)
    set_tests_properties(view.events_gravity PROPERTIES RESOURCE_LOCK xvfb)
endif()
