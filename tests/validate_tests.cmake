# `carom validate` from the command line (included by tests/CMakeLists.txt,
# whose carom_cli_test and out it uses): bad values are refused before any
# run and leave no output behind (${out} is the JSON), and the quick suite
# passes.
set(refused ${CMAKE_CURRENT_BINARY_DIR}/validate-refused)
set(validate "validate|--quick|--report|${refused}|--json|${out}")
carom_cli_test(validate_zero_dt fail "--dt must be in \\(0, 0.05\\], got 0" "${validate}|--dt|0")
carom_cli_test(validate_large_dt fail "--dt must be in \\(0, 0.05\\], got 0.1" "${validate}|--dt|0.1")
carom_cli_test(validate_nan_dt fail "--dt must be in \\(0, 0.05\\], got nan" "${validate}|--dt|nan")
carom_cli_test(validate_few_particles fail "--particles: '10' is out of range; allowed: whole numbers from 256 to 1000000"
               "${validate}|--particles|10")
carom_cli_test(validate_zero_particles fail "--particles: '0' is out of range; allowed: whole numbers from 256 to 1000000"
               "${validate}|--particles|0")
carom_cli_test(validate_negative_particles fail "--particles" "${validate}|--particles|-5")
carom_cli_test(validate_unknown_backend fail "--backend: cuda not in \\{cpu" "${validate}|--backend|cuda")
carom_cli_test(validate_unknown_pipeline fail "--pipeline: fast not in \\{auto,host-grid,resident\\}"
               "${validate}|--pipeline|fast")
carom_cli_test(validate_resident_on_cpu fail "--pipeline resident needs --backend opencl"
               "${validate}|--backend|cpu|--pipeline|resident")
carom_cli_test(validate_seed_renamed fail
               "--pipeline seed is now called host-grid; the old name still works.*--pipeline host-grid needs --backend opencl"
               "${validate}|--backend|cpu|--pipeline|seed")
carom_cli_test(validate_seed_not_a_number fail "--seed.*many" "${validate}|--seed|many")
carom_cli_test(validate_unwritable_json fail "--json '/nonexistent-dir/validate.json': the folder '/nonexistent-dir' does not exist"
               "validate|--quick|--report|${refused}|--json|/nonexistent-dir/validate.json")
carom_cli_test(validate_report_not_a_folder fail "--report '/dev/null/report': '/dev/null' is not a folder"
               "validate|--quick|--report|/dev/null/report|--json|${out}")
if(OpenCL_FOUND)
    carom_cli_test(validate_device_out_of_range fail "device 99 \\(WorldDef::device, --device\\): no such device index"
                   "${validate}|--backend|opencl|--device|99")
endif()

# The quick suite itself, about 35 s of one core, 10 s of it the
# event-driven section, which runs on the CPU whatever --backend says (the
# OpenCL conservation runs are listed as not run until the OpenCL backend
# runs the pairwise scheme). It runs alone and on one OpenMP thread: the CPU backend's threads
# meet at a barrier several times a step, and when other processes hold the
# cores each meeting waits for a time slice, which made a two-thread run take
# over 20 minutes beside a parallel build. Its results do not depend on the
# thread count (the backend sums in a fixed order).
add_test(NAME validate.quick
         COMMAND $<TARGET_FILE:carom> validate --quick --report ${CMAKE_CURRENT_BINARY_DIR}/validation-quick
                 --json ${CMAKE_CURRENT_BINARY_DIR}/validation-quick.json)
set_tests_properties(validate.quick PROPERTIES TIMEOUT 1200 RUN_SERIAL TRUE ENVIRONMENT OMP_NUM_THREADS=1
                                               LABELS "validate;slow")
