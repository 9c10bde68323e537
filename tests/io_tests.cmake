# Scene files, trajectories, statistics and checkpoints from the command line
# (included by tests/CMakeLists.txt, whose carom_cli_test, run, data and out it uses).

# Every shipped scene runs from the command line (a few steps; the doctest
# suite runs them whole on each backend).
file(GLOB scenes ${PROJECT_SOURCE_DIR}/scenes/*.toml)
foreach(scene IN LISTS scenes)
    get_filename_component(name ${scene} NAME_WE)
    carom_cli_test(scene_${name} pass "\"escaped\": 0" "run|--backend|cpu|--scene|${scene}|--steps|20|--json")
endforeach()

# Refusals: a message naming file, line, key and value, a non-zero exit, and
# no output file left behind (${out} is also the trajectory here).
set(traj "--trajectory|${out}")
carom_cli_test(scene_typo fail "scene_typo.toml:5: unknown key 'group\\[1\\].raduis'; allowed in group\\[1\\]: count"
               "run|--backend|cpu|--scene|${data}/scene_typo.toml|${traj}")
carom_cli_test(scene_missing fail "cannot read scene file '.*no-such.toml': No such file or directory"
               "run|--backend|cpu|--scene|${data}/no-such.toml|--output-state|${out}")
# A scene file is read as every text input is: a device without end is refused at its first NUL byte.
carom_cli_test(scene_dev_zero fail "scene file '/dev/zero': a NUL byte, which no text file has"
               "run|--backend|cpu|--scene|/dev/zero|--output-state|${out}")
carom_cli_test(scene_group_option_ambiguous fail
               "--particles sets the particle group of a scene, but '.*two_groups.toml' has 2 \\[\\[group\\]\\] tables"
               "run|--backend|cpu|--scene|${data}/two_groups.toml|--particles|5|--output-state|${out}")
carom_cli_test(scene_bad_override fail "dt must be a finite number > 0, got 0"
               "run|--backend|cpu|--scene|${data}/two_groups.toml|--dt|0|--output-state|${out}")
carom_cli_test(scene_with_input_state fail "--input-state excludes --scene"
               "run|--scene|${data}/two_groups.toml|--input-state|${data}/two_disks.csv|--box|10|10")
carom_cli_test(scene_two_groups_run pass "\"particles\": 40"
               "run|--backend|cpu|--scene|${data}/two_groups.toml|--steps|5|--json")
carom_cli_test(resume_missing fail "cannot read checkpoint '.*no-such.ckpt': no such file"
               "run|--backend|cpu|--resume|${data}/no-such.ckpt|--output-state|${out}")
carom_cli_test(resume_not_a_checkpoint fail "checkpoint '.*two_disks.csv': not a carom checkpoint"
               "run|--backend|cpu|--resume|${data}/two_disks.csv|${traj}")
carom_cli_test(resume_with_scene_option fail "--dt excludes --resume"
               "run|--backend|cpu|--resume|${data}/two_disks.csv|--dt|0.1")
carom_cli_test(resume_with_collisions fail "--collisions excludes --resume"
               "run|--backend|cpu|--resume|${data}/version1.ckpt|--collisions|pairwise")
# A version-1 checkpoint, written by carom before the collision schemes (at
# step 10), continues with the simultaneous scheme.
carom_cli_test(resume_version1 pass "\"scheme\": \"simultaneous\",.*\"step\": 20,"
               "run|--backend|cpu|--resume|${data}/version1.ckpt|--steps|10|--json")
carom_cli_test(every_zero fail "--every: '0' is out of range; allowed: whole numbers from 1 to" "${run}|--every|0")
# Counts read as bench --sizes reads them: with an exponent, whole.
carom_cli_test(particles_exponent pass "\"particles\": 10000," "run|--backend|cpu|--steps|1|--particles|1e4|--json")
carom_cli_test(particles_fraction fail "--particles: '2.5e0' is not a number of particles; allowed: whole numbers from 1 to"
               "${run}|--particles|2.5e0")
carom_cli_test(too_many_particles fail "--particles: '1000000001' is out of range; allowed: whole numbers from 1 to 1000000000"
               "${run}|--particles|1000000001")
carom_cli_test(unwritable_trajectory fail "--trajectory '/nonexistent-dir/t.xyz': the folder '/nonexistent-dir' does not exist"
               "${run}|--trajectory|/nonexistent-dir/t.xyz")
carom_cli_test(same_file_twice fail "--stats and --output-state name the same file"
               "${run}|--stats|${out}")
carom_cli_test(unwritable_checkpoint fail "--checkpoint '/nonexistent-dir/c.ckpt': the folder '/nonexistent-dir' does not exist"
               "${run}|--checkpoint|/nonexistent-dir/c.ckpt")

# The output files read back by the tools users read them with (ASE for the
# trajectory), resumed runs put end to end, and Ctrl-C.
find_package(Python3 COMPONENTS Interpreter)
if(NOT Python3_Interpreter_FOUND)
    message(WARNING "python3 not found (./install-deps.sh --test installs it): the output file tests are not run")
    return()
endif()
# AddressSanitizer reserves terabytes of address space, so the tests that
# limit it (ulimit -v) are skipped in a sanitized build.
set(sanitized "")
if(CMAKE_CXX_FLAGS MATCHES "-fsanitize=[^ ]*address")
    set(sanitized --sanitized)
endif()
set(backends cpu)
if(OpenCL_FOUND)
    set(backends cpu,opencl)
endif()
foreach(test IN ITEMS trajectory_reads_in_ase periodic_trajectory_reads_in_ase stats_csv checkpoint_layout resume_continues_bit_for_bit
                      interrupt_writes_everything scene_outputs_and_overrides json_and_quiet_print_no_progress
                      energy_warning blow_up_stops_cleanly special_files
                      same_file_under_two_spellings outputs_never_replace_inputs
                      resume_appends_to_its_outputs empty_output_names_are_refused stop_signals_keep_every_output
                      output_failure_keeps_the_others output_failures_at_the_end_are_all_reported
                      stdout_write_errors_are_reported
                      blow_up_names_step_and_particle small_runs_start_no_thread_team fifo_reader_gone_keeps_the_others
                      empty_numbers_are_refused memory_check_uses_available_memory input_state_fifo
                      resume_forged_count_allocates_nothing two_signals_at_once_stop_the_run
                      every_subcommand_checks_its_files_first empty_file_names_are_refused
                      failed_first_sample_keeps_earlier_files same_file_through_a_symlinked_folder
                      same_file_through_a_bind_mount resume_refuses_a_gap_or_another_simulation
                      output_that_is_standard_output_or_error huge_last_line_is_refused_at_once
                      signal_at_start_up_ends_at_once bench_and_validate_stop_on_signals
                      second_signal_removes_temporary_files append_copy_failure_is_named append_copy_on_a_full_disk
                      signal_ends_the_wait_for_a_fifo_reader periodic_gravity_energy
                      signal_stops_within_a_long_step)
    add_test(NAME outputs.${test}
             COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/outputs_test.py --carom $<TARGET_FILE:carom>
                     --work ${CMAKE_CURRENT_BINARY_DIR}/outputs --backends ${backends} ${sanitized} ${test})
endforeach()

# Every output reaches the disk before it is renamed into place, and its
# folder after: fsync and rename are logged by a library preloaded into carom
# (Linux; not beside AddressSanitizer, which must be loaded first).
if(CMAKE_SYSTEM_NAME STREQUAL "Linux" AND NOT sanitized)
    add_library(fsync_spy MODULE fsync_spy.cpp)
    target_link_libraries(fsync_spy PRIVATE ${CMAKE_DL_LIBS})
    add_test(NAME outputs.synced_before_rename
             COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/outputs_test.py --carom $<TARGET_FILE:carom>
                     --work ${CMAKE_CURRENT_BINARY_DIR}/outputs --spy $<TARGET_FILE:fsync_spy> synced_before_rename)
endif()
