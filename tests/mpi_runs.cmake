# carom run under mpirun against one process: what both write must be the
# same bytes (the final state, statistics, trajectory and checkpoint, and the
# JSON summary but for its timings, memory, device and the processes' costs).
#   -DCAROM=<binary> -DMPIEXEC=<mpiexec;its flags> -DWORK_DIR=<dir> -DMODE=<mode>
#   -DARGS=<run options, '|'-separated> -DRUNS=<processes[:NX:NY], ';'-separated>
# MODE identity: a run in one process, then one for each entry of RUNS.
# MODE resume: half the steps on RUNS' first entry, resumed from its
#   checkpoint on each other entry (1 = one process without mpirun), against
#   the whole run in one process.
# MODE signal: a run on RUNS' first entry stopped by SIGTERM to mpirun (sh): its
#   state and checkpoint name the same step, and the checkpoint resumes.
string(REPLACE "|" ";" args "${ARGS}")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

# Runs carom on `processes` (1: no mpirun) with the run options in ARGN,
# writing ${WORK_DIR}/<tag>.*; fails the test unless it exits 0.
function(run_carom tag processes)
    set(command ${CAROM})
    if(NOT processes STREQUAL "1")
        string(REPLACE ":" ";" split "${processes}")
        list(GET split 0 count)
        set(command ${MPIEXEC} -np ${count} ${CAROM})
        list(LENGTH split parts)
        if(parts EQUAL 3)
            list(GET split 1 x)
            list(GET split 2 y)
            set(domains --domains ${x} ${y})
        endif()
    endif()
    set(out "${WORK_DIR}/${tag}")
    execute_process(COMMAND ${command} run ${ARGN} ${domains} --quiet --json --output-state ${out}.csv
                            --stats ${out}.stats.csv --checkpoint ${out}.ckpt --trajectory ${out}.xyz
                    RESULT_VARIABLE status OUTPUT_FILE ${out}.json ERROR_VARIABLE err)
    if(NOT status EQUAL 0)
        message(FATAL_ERROR "carom on ${processes} processes (${command} run ${ARGN}) exited ${status}: ${err}")
    endif()
    # Split, not each process stepping the whole world (that too would match).
    if(NOT processes STREQUAL "1")
        file(READ "${out}.json" json)
        if(NOT json MATCHES "process 0 of ${count} \\(")
            message(FATAL_ERROR "carom on ${processes} processes did not split the world: ${json}")
        endif()
    endif()
endfunction()

# The JSON summary without what differs between runs of the same world: the
# timings, memory, device and the processes' costs.
function(summary tag result)
    file(READ "${WORK_DIR}/${tag}.json" json)
    foreach(key IN ITEMS wall_seconds particle_steps_per_second memory device processes)
        string(JSON json ERROR_VARIABLE absent REMOVE "${json}" ${key})
    endforeach()
    set(${result} "${json}" PARENT_SCOPE)
endfunction()

# The files of run `tag` against those of run `expected`, and with SUMMARY their summaries.
function(require_same expected tag what)
    foreach(file IN ITEMS csv stats.csv ckpt xyz)
        execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK_DIR}/${expected}.${file}"
                                "${WORK_DIR}/${tag}.${file}" RESULT_VARIABLE differ)
        if(differ)
            message(FATAL_ERROR "${what}: ${tag}.${file} differs from ${expected}.${file}")
        endif()
    endforeach()
    if(ARGN STREQUAL "SUMMARY")
        summary(${expected} one)
        summary(${tag} other)
        if(NOT one STREQUAL other)
            message(FATAL_ERROR "${what}: the summaries differ:\n${one}\n${other}")
        endif()
    endif()
endfunction()

if(MODE STREQUAL "identity")
    run_carom(one 1 ${args})
    foreach(processes IN LISTS RUNS)
        string(REPLACE ":" "-" tag "p${processes}")
        run_carom(${tag} ${processes} ${args})
        require_same(one ${tag} "${processes} processes" SUMMARY)
    endforeach()
elseif(MODE STREQUAL "resume")
    # STEPS steps whole, then STEPS / 2 and the rest resumed.
    math(EXPR half "${STEPS} / 2")
    run_carom(whole 1 ${args} --steps ${STEPS})
    list(GET RUNS 0 first)
    run_carom(half ${first} ${args} --steps ${half})
    list(SUBLIST RUNS 1 -1 rest)
    foreach(processes IN LISTS rest)
        string(REPLACE ":" "-" tag "resumed${processes}")
        file(COPY_FILE "${WORK_DIR}/half.ckpt" "${WORK_DIR}/${tag}.ckpt")
        file(COPY_FILE "${WORK_DIR}/half.stats.csv" "${WORK_DIR}/${tag}.stats.csv")
        file(COPY_FILE "${WORK_DIR}/half.xyz" "${WORK_DIR}/${tag}.xyz")
        run_carom(${tag} ${processes} --resume "${WORK_DIR}/${tag}.ckpt" --steps ${half} --every ${EVERY})
        require_same(whole ${tag} "resumed on ${processes} processes")
    endforeach()
elseif(MODE STREQUAL "signal")
    list(GET RUNS 0 count)
    set(out "${WORK_DIR}/stopped")
    # SIGTERM to mpirun, which hands it to every process, once the run is
    # stepping: its first checkpoint (step 0) is written.
    list(JOIN MPIEXEC " " launch)
    list(JOIN args " " options)
    set(run "${launch} -np ${count} ${CAROM} run ${options} --steps 100000000 --every 50 --quiet --output-state ${out}.csv --checkpoint ${out}.ckpt")
    execute_process(COMMAND sh -c "${run} & pid=$!; while [ ! -e ${out}.ckpt ]; do sleep 0.1; done; sleep 1; kill -TERM $pid; wait $pid"
                    RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE err TIMEOUT 120)
    if(status EQUAL 0 OR NOT err MATCHES "interrupted at step ([0-9]+) of 100000000 by SIGTERM")
        message(FATAL_ERROR "expected a stop by SIGTERM, got exit ${status}:\n${output}${err}")
    endif()
    set(step ${CMAKE_MATCH_1})
    if(NOT err MATCHES "checkpoint ${out}.ckpt: step ${step}\n" OR NOT err MATCHES "final state ${out}.csv: step ${step}\n")
        message(FATAL_ERROR "the outputs are not all at step ${step}:\n${err}")
    endif()
    # The checkpoint holds that step: resumed for 0 steps, it gives the same state.
    execute_process(COMMAND ${CAROM} run --resume ${out}.ckpt --steps 0 --quiet --output-state ${out}-resumed.csv
                    RESULT_VARIABLE status ERROR_VARIABLE err)
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${out}.csv ${out}-resumed.csv RESULT_VARIABLE differ)
    if(NOT status EQUAL 0 OR differ)
        message(FATAL_ERROR "the checkpoint at step ${step} does not give the state written there (${status}): ${err}")
    endif()
else()
    message(FATAL_ERROR "MODE=${MODE}: allowed: identity, resume, signal")
endif()
