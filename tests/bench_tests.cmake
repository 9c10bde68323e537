# `carom bench` and `--pipeline` from the command line (included by
# tests/CMakeLists.txt, whose carom_cli_test, run and out it uses). Speed is
# benchmarked, never asserted: these check that the runs work and that bad
# values are refused (and leave no output file behind: ${out} is the JSON).
set(bench "bench|--json|${out}")
carom_cli_test(bench_list pass "naive-cpu +all pairs" "bench|--list")
carom_cli_test(bench_small pass "cpu +simultaneous +100 .*naive-cpu +simultaneous +200 "
               "bench|--methods|cpu,naive-cpu|--sizes|200,1e2|--samples|1")
# --quick measures both schemes by default: each grid method's pairwise row, with its pw/sim ratio, follows its
# simultaneous one; the naive methods run simultaneous only (cli.bench_outputs counts the rows).
carom_cli_test(bench_schemes pass
               "naive-cpu +simultaneous +1000 .*cpu +simultaneous +1000 .*cpu +pairwise +1000 +[0-9.e+-]+ +[0-9.e+-]+ +[0-9.]+x .*cpu +pairwise +4000 "
               "bench|--methods|cpu,naive-cpu|--quick")
# The events method: its own table of rates (never the step columns), at every N; only it runs the events scheme.
carom_cli_test(bench_events_quick pass
               "event-driven, periodic box.*method +N +collisions/s +particle-time/s +events/s.*events +1000 +[0-9.e+]+ +[0-9.e+]+ +[0-9.e+]+ .*events +4000 +[0-9.e+]+ "
               "bench|--methods|events,cpu|--collisions|events|--quick")
carom_cli_test(bench_events_at_rest fail "--speed 0: the events method times collisions, and disks at rest never collide"
               "bench|--methods|events|--sizes|1000|--speed|0")
carom_cli_test(bench_events_cpu_only fail "--collisions events: none of the methods chosen runs the events scheme"
               "${bench}|--methods|cpu,naive-cpu|--collisions|events")
carom_cli_test(bench_events_stepped_only fail "--collisions simultaneous,pairwise: none of the methods chosen runs"
               "${bench}|--methods|events|--collisions|simultaneous,pairwise")
carom_cli_test(bench_collisions_unknown fail "--collisions: unknown collision scheme 'sideways'; allowed: pairwise, simultaneous, events"
               "${bench}|--collisions|sideways")
carom_cli_test(bench_pairwise_naive_only fail "--collisions pairwise: none of the methods chosen runs the pairwise scheme"
               "${bench}|--methods|naive-cpu|--collisions|pairwise")
carom_cli_test(bench_size_zero fail "--sizes: '0' is out of range" "${bench}|--sizes|0")
carom_cli_test(bench_size_fraction fail "--sizes: '1.5' is not a number of particles" "${bench}|--sizes|1.5")
carom_cli_test(bench_size_text fail "--sizes: 'many' is not a number of particles" "${bench}|--sizes|many")
carom_cli_test(bench_unknown_method fail "--methods: unknown method 'warp'; allowed: naive-cpu" "${bench}|--methods|warp")
carom_cli_test(bench_packing_too_high fail "packing must be in \\(0, 0.7\\], got 0.9" "${bench}|--packing|0.9")
carom_cli_test(bench_negative_radius fail "radius must be a finite number > 0, got -1" "${bench}|--radius|-1")
carom_cli_test(bench_zero_dt fail "dt must be a finite number > 0, got 0" "${bench}|--dt|0")
carom_cli_test(bench_zero_budget fail "--budget-ms must be a finite number > 0, got 0" "${bench}|--budget-ms|0")
carom_cli_test(bench_zero_samples fail "--samples: '0' is out of range; allowed: whole numbers from 1 to 1000" "${bench}|--samples|0")
carom_cli_test(bench_unwritable_json fail "--json '/nonexistent-dir/bench.json': the folder '/nonexistent-dir' does not exist"
               "bench|--methods|cpu|--sizes|100|--json|/nonexistent-dir/bench.json")
add_test(NAME cli.bench_outputs
         COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_bench_outputs.cmake)
# --profile under the pairwise scheme at N disks: the parts each method's profile must show.
function(carom_bench_profile_test name methods particles parts)
    add_test(NAME cli.bench_profile_${name}
             COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DJSON=${CMAKE_CURRENT_BINARY_DIR}/bench-profile-${name}.json
                     -DMETHODS=${methods} -DPARTICLES=${particles} "-DPARTS=${parts}"
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/cli_bench_profile.cmake)
endfunction()
carom_bench_profile_test(cpu_pairwise cpu 500 "neighbour lists (host, 1 thread)")
if(OpenCL_FOUND)
    carom_cli_test(run_resident pass "\"backend\": \"opencl\".*\"device_bytes_peak\": [1-9]"
                   "run|--backend|opencl|--pipeline|resident|--particles|100|--steps|10|--json")
    carom_cli_test(pipeline_unknown fail "--pipeline: fast not in \\{auto,host-grid,resident\\}" "${run}|--pipeline|fast")
    carom_cli_test(pipeline_resident_on_cpu fail "--pipeline: 'resident' needs --backend opencl"
                   "${run}|--pipeline|resident")
    # seed, host-grid's former name (--pipeline) and opencl-host-grid's (--methods): still read, with a notice.
    carom_cli_test(pipeline_seed_renamed pass
                   "backend +opencl on .*, host-grid pipeline.*carom: --pipeline seed is now called host-grid; the old name still works"
                   "run|--backend|opencl|--pipeline|seed|--particles|100|--steps|10")
    carom_cli_test(bench_opencl_seed_renamed pass
                   "opencl-host-grid +simultaneous +100 .*carom: --methods opencl-seed is now called opencl-host-grid; the old name still works"
                   "bench|--methods|opencl-seed|--collisions|simultaneous|--sizes|100|--samples|1")
    carom_bench_profile_test(host_grid_pairwise opencl-host-grid 500
        "buildGrid (host)|upload grid|findEvents|resolveRoundsInGroup|finishStepById|read list lengths|download state")
    # Above and below the resident pipeline's small-system limit (2 048 disks).
    carom_bench_profile_test(resident_pairwise opencl-resident 3000
        "scanCountsIntoCells|scatterToCells|sortCellSegments|findEvents|resolveRoundsInGroup|finishPairwiseAndCount|read list lengths")
    carom_bench_profile_test(resident_small_pairwise opencl-resident 500 "stepSmallPairwise|read list lengths")
endif()
