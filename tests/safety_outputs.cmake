# Outputs that would write over each other or over the run's own inputs are
# refused before any work, under any spelling (issue 11, items 1 and 2; the
# hard links, symlinks, special files and resumed runs are in outputs_test.py).
# Included by tests/CMakeLists.txt, whose carom_cli_test and data it uses.
set(safety ${CMAKE_CURRENT_BINARY_DIR}/safety-outputs)
file(MAKE_DIRECTORY ${safety})
set(small "run|--backend|cpu|--particles|10|--steps|5")
carom_cli_test(same_file_checkpoint_and_state fail
               "--checkpoint and --output-state name the same file \\('.*c.ckpt' and '.*/./c.ckpt'\\)"
               "${small}|--checkpoint|${safety}/c.ckpt|--output-state|${safety}/./c.ckpt")
carom_cli_test(same_file_trajectory_and_stats fail "--trajectory and --stats name the same file"
               "${small}|--trajectory|${safety}/t.xyz|--stats|${safety}/./t.xyz")
carom_cli_test(same_file_stats_and_state fail "--stats and --output-state name the same file"
               "${small}|--stats|${safety}/a.csv|--output-state|${safety}/sub/../a.csv")
carom_cli_test(same_file_temporary_name fail
               "--trajectory '.*s.csv.ab12cd.partial' is a temporary name of --stats '.*s.csv'"
               "${small}|--stats|${safety}/s.csv|--trajectory|${safety}/s.csv.ab12cd.partial")

# Fresh copies for each run (a regression overwrites them, never the source tree).
file(WRITE ${safety}/originals/self.toml
     "box = [20, 20]\nsteps = 5\n[[group]]\ncount = 10\ntemperature = 1\n[output]\nstate = \"${safety}/self.toml\"\n")
configure_file(${data}/two_disks.csv ${safety}/originals/in.csv COPYONLY)
configure_file(${data}/version1.ckpt ${safety}/originals/in.ckpt COPYONLY)
configure_file(${data}/version1.ckpt ${safety}/originals/resumed.ckpt COPYONLY)
add_test(NAME cli.safety_outputs_inputs
         COMMAND ${CMAKE_COMMAND} -E copy ${safety}/originals/self.toml ${safety}/originals/in.csv
                 ${safety}/originals/in.ckpt ${safety}/originals/resumed.ckpt ${safety})
set_tests_properties(cli.safety_outputs_inputs PROPERTIES FIXTURES_SETUP safety_outputs_inputs)
carom_cli_test(output_over_input_state fail "--output-state '.*in.csv' would overwrite the input --input-state"
               "run|--backend|cpu|--input-state|${safety}/in.csv|--box|10|10|--output-state|${safety}/./in.csv")
carom_cli_test(output_over_resumed_checkpoint fail "--output-state '.*in.ckpt' would overwrite the input --resume"
               "run|--backend|cpu|--resume|${safety}/in.ckpt|--output-state|${safety}/in.ckpt")
carom_cli_test(output_over_scene_file fail "output.state '.*self.toml' would overwrite the input --scene"
               "run|--backend|cpu|--scene|${safety}/self.toml")
# The one file that may be both: a checkpoint resumed from and replaced whole by --checkpoint.
carom_cli_test(resume_replaces_its_checkpoint pass "wrote +.*resumed.ckpt \\(step [0-9]+\\)"
               "run|--backend|cpu|--resume|${safety}/resumed.ckpt|--checkpoint|${safety}/./resumed.ckpt|--steps|5")
set_tests_properties(cli.output_over_input_state cli.output_over_resumed_checkpoint cli.output_over_scene_file
                     cli.resume_replaces_its_checkpoint PROPERTIES FIXTURES_REQUIRED safety_outputs_inputs)
