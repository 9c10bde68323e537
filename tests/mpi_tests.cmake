# Several processes, one world: carom run under mpirun writes the bytes one
# process writes, whatever the number of processes and the domains.
if(NOT CAROM_HAVE_MPI OR NOT MPIEXEC_EXECUTABLE)
    message(STATUS "MPI not found: the tests of runs under mpirun are not built")
    return()
endif()
set(mpiexec ${MPIEXEC_EXECUTABLE})
execute_process(COMMAND ${MPIEXEC_EXECUTABLE} --version OUTPUT_VARIABLE mpiexec_version ERROR_QUIET)
if(mpiexec_version MATCHES "Open MPI|OpenRTE")
    list(APPEND mpiexec --oversubscribe)  # more processes than this machine has cores
endif()
# Open MPI refuses root unless told (containers, CI). Its components, unloaded
# by MPI_Finalize, leave allocations behind that LeakSanitizer cannot name, so
# leaks are not looked for under mpirun (the rest of the suite looks for them).
set(mpi_environment "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMP_NUM_THREADS=1;ASAN_OPTIONS=detect_leaks=0")

function(carom_mpi_test name mode runs args)
    string(REPLACE ";" "|" args "${args}")
    add_test(NAME mpi.${name}
             COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> "-DMPIEXEC=${mpiexec}" -DMODE=${mode}
                     "-DRUNS=${runs}" "-DARGS=${args}" -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/mpi/${name} ${ARGN}
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/mpi_runs.cmake)
    set_tests_properties(mpi.${name} PROPERTIES ENVIRONMENT "${mpi_environment}" PROCESSORS 2)
endfunction()

# 2 processes (1 x 2 domains), 3 (3 x 1), 4 as 2 x 2 and as 4 x 1. Polydisperse
# disks of unequal masses, so that ties and sums are exercised.
set(disks --backend cpu --particles 2000 --packing 0.5 --radius-min 0.5 --radius-max 1 --mass-min 1 --mass-max 3
          --every 20)
set(runs "2;3;4:2:2;4:4:1")
carom_mpi_test(pairwise_walls_gravity identity "${runs}" "${disks};--steps;200;--gravity;0;-0.05")
carom_mpi_test(pairwise_periodic identity "${runs}" "${disks};--steps;200;--boundary;periodic")
carom_mpi_test(simultaneous_walls_gravity identity "${runs}"
               "${disks};--steps;200;--gravity;0;-0.05;--collisions;simultaneous")
carom_mpi_test(simultaneous_periodic identity "${runs}" "${disks};--steps;200;--boundary;periodic;--collisions;simultaneous")
# Fast disks in a small periodic box on 2 x 2 domains: many cross every edge
# and corner of a domain, and the box's own edges, each substep.
carom_mpi_test(migration identity "4:2:2;4:1:4"
               "--backend;cpu;--particles;400;--packing;0.3;--speed;20;--steps;300;--boundary;periodic;--every;50")
# A pulse down a row of 40 touching disks, 40 collision rounds in one step,
# across 1 and 3 domain boundaries: the halo must deepen with the rounds.
carom_mpi_test(pulse_across_domains identity "2:2:1;4:4:1"
               "--backend;cpu;--scene;${CMAKE_CURRENT_SOURCE_DIR}/data/mpi_cradle.toml;--every;10")
# A checkpoint of 4 processes resumed on 2 and in one process.
carom_mpi_test(checkpoint_resumed resume "4;2;1" "${disks};--boundary;periodic;--gravity;0;-0.05" -DSTEPS=200 -DEVERY=20)
carom_mpi_test(signal signal "2" "--backend;cpu;--particles;20000")
# The OpenCL engines step the domains too (on PoCL here): the small system's
# one work-group and the launches of larger shares, both schemes; the
# resident engine keeps its disks on the device (OpenClDomainShare), the
# host-grid one on the host.
if(OpenCL_FOUND)
    set(opencl_disks --backend opencl --packing 0.5 --radius-min 0.5 --radius-max 1 --mass-min 1 --mass-max 3 --every 20)
    carom_mpi_test(opencl_resident_small identity "2;4:2:2"
                   "${opencl_disks};--pipeline;resident;--particles;1500;--steps;100;--gravity;0;-0.05")
    carom_mpi_test(opencl_resident identity "2"
                   "${opencl_disks};--pipeline;resident;--particles;8000;--steps;60;--boundary;periodic")
    carom_mpi_test(opencl_host_grid identity "3"
                   "${opencl_disks};--pipeline;host-grid;--particles;3000;--steps;60;--collisions;simultaneous")
    carom_mpi_test(opencl_migration identity "4:2:2"
                   "--backend;opencl;--pipeline;resident;--particles;12000;--packing;0.3;--speed;20;--steps;40;--boundary;periodic;--every;20")
    carom_mpi_test(opencl_resident_simultaneous identity "2:2:1"
                   "${opencl_disks};--pipeline;resident;--particles;8000;--steps;60;--collisions;simultaneous;--boundary;periodic")
endif()

# carom on `processes` under mpirun: its exit (`expect`: pass or fail) and process 0's output.
function(carom_mpi_expect name processes expect regex args)
    list(SUBLIST mpiexec 1 -1 flags)
    string(REPLACE ";" "|" args "${flags};-np;${processes};$<TARGET_FILE:carom>;${args}")
    add_test(NAME mpi.${name}
             COMMAND ${CMAKE_COMMAND} -DCAROM=${MPIEXEC_EXECUTABLE} "-DARGS=${args}" -DEXPECT=${expect}
                     "-DOUTPUT_REGEX=${regex}" -DABSENT_FILE=${CMAKE_CURRENT_BINARY_DIR}/mpi/${name}.csv
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_cli.cmake)
    set_tests_properties(mpi.${name} PROPERTIES ENVIRONMENT "${mpi_environment}" TIMEOUT 60 PROCESSORS 2)
endfunction()
# Refusals: a message on process 0 and a non-zero exit from every process, never a hang.
function(carom_mpi_refusal name processes regex args)
    carom_mpi_expect(${name} ${processes} fail "${regex}" "${args}")
endfunction()
# carom bench splits each world of the methods that step one, and refuses the others.
carom_mpi_expect(bench 2 pass "split  among 2 processes.*cpu +pairwise +4000"
                 "bench|--quick|--methods|cpu|--collisions|simultaneous,pairwise")
carom_mpi_refusal(bench_naive 2 "--methods naive-cpu: runs in one process; allowed under mpirun"
                  "bench|--quick|--methods|naive-cpu")
# A blow-up (the simultaneous scheme under strong gravity) is reported at the
# step and particle one process names.
carom_mpi_refusal(blow_up 2 "steps 501 to 600 failed: the state went non-finite at step 508: particle 312 "
                  "run|--backend|cpu|--particles|2000|--packing|0.3|--gravity|0|-10|--collisions|simultaneous|--steps|2000")
carom_cli_test(blow_up_one_process fail "the state went non-finite at step 508: particle 312 "
               "run|--backend|cpu|--particles|2000|--packing|0.3|--gravity|0|-10|--collisions|simultaneous|--steps|2000")

set(refused "run|--backend|cpu|--steps|5|--output-state|${CMAKE_CURRENT_BINARY_DIR}/mpi")
file(MAKE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/mpi)
carom_mpi_refusal(domains_not_processes 2 "domains 3 x 1 for 2 processes; allowed: two positive numbers whose product is 2"
                  "${refused}/domains_not_processes.csv;--domains;3;1")
carom_mpi_refusal(domains_thinner_than_cells 4 "domains 4 x 1 on a grid of 3 x 3 cells.*allowed: at most one domain per cell"
                  "${refused}/domains_thinner_than_cells.csv;--particles;4;--box;8;8;--domains;4;1")
carom_mpi_refusal(events_scheme 2 "CollisionScheme::Events runs in one process; allowed in a decomposed world: Pairwise, Simultaneous"
                  "${refused}/events_scheme.csv;--collisions;events")
# Two processes given their own arguments (mpirun's MPMD form, `first` and
# `second`, each '|'-separated), refused with process 0's message.
function(carom_mpi_two_refusal name regex first second)
    list(SUBLIST mpiexec 1 -1 flags)
    string(REPLACE ";" "|" flags "${flags}")
    set(args "${flags}|-np|1|$<TARGET_FILE:carom>|${first}|:|-np|1|$<TARGET_FILE:carom>|${second}")
    add_test(NAME mpi.${name}
             COMMAND ${CMAKE_COMMAND} -DCAROM=${MPIEXEC_EXECUTABLE} "-DARGS=${args}" -DEXPECT=fail
                     "-DOUTPUT_REGEX=${regex}" -P ${CMAKE_CURRENT_SOURCE_DIR}/expect_cli.cmake)
    set_tests_properties(mpi.${name} PROPERTIES ENVIRONMENT "${mpi_environment}" TIMEOUT 60 PROCESSORS 2)
endfunction()
# A device missing on one process's node: process 0 names it.
carom_mpi_two_refusal(device_missing_on_one_process "carom: error: process 1 of 2: device 99 .*no such device|needs OpenCL"
                      "run|--backend|opencl|--steps|5" "run|--backend|opencl|--device|99|--steps|5")
carom_mpi_two_refusal(different_arguments "the processes were given different worlds or disks"
                      "run|--backend|cpu|--steps|5|--seed|1" "run|--backend|cpu|--steps|5|--seed|2")
