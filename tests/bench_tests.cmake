# `carom bench` and `--pipeline` from the command line (included by
# tests/CMakeLists.txt, whose carom_cli_test, run and out it uses). Speed is
# benchmarked, never asserted: these check that the runs work and that bad
# values are refused (and leave no output file behind: ${out} is the JSON).
set(bench "bench|--json|${out}")
carom_cli_test(bench_list pass "naive-cpu +all pairs" "bench|--list")
carom_cli_test(bench_small pass "cpu +100 .*naive-cpu +200 " "bench|--methods|cpu,naive-cpu|--sizes|200,1e2|--samples|1")
carom_cli_test(bench_size_zero fail "--sizes: '0' is not a number of particles" "${bench}|--sizes|0")
carom_cli_test(bench_size_fraction fail "--sizes: '1.5' is not a number of particles" "${bench}|--sizes|1.5")
carom_cli_test(bench_size_text fail "--sizes: 'many' is not a number of particles" "${bench}|--sizes|many")
carom_cli_test(bench_unknown_method fail "--methods: unknown method 'warp'; allowed: naive-cpu" "${bench}|--methods|warp")
carom_cli_test(bench_packing_too_high fail "packing must be in \\(0, 0.7\\], got 0.9" "${bench}|--packing|0.9")
carom_cli_test(bench_negative_radius fail "radius must be a finite number > 0, got -1" "${bench}|--radius|-1")
carom_cli_test(bench_zero_dt fail "dt must be a finite number > 0, got 0" "${bench}|--dt|0")
carom_cli_test(bench_zero_budget fail "--budget-ms must be a finite number > 0, got 0" "${bench}|--budget-ms|0")
carom_cli_test(bench_zero_samples fail "--samples: Value 0 not in range 1 to 1000" "${bench}|--samples|0")
carom_cli_test(bench_unwritable_json fail "cannot write '/nonexistent-dir/bench.json'"
               "bench|--methods|cpu|--sizes|100|--json|/nonexistent-dir/bench.json")
add_test(NAME cli.bench_outputs
         COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_bench_outputs.cmake)
if(OpenCL_FOUND)
    carom_cli_test(run_resident pass "\"backend\": \"opencl\""
                   "run|--backend|opencl|--pipeline|resident|--particles|100|--steps|10|--json")
    carom_cli_test(pipeline_unknown fail "--pipeline: fast not in \\{seed,resident\\}" "${run}|--pipeline|fast")
    carom_cli_test(pipeline_resident_on_cpu fail "--pipeline resident needs --backend opencl"
                   "${run}|--pipeline|resident")
endif()
