# Builds examples/ as a project of its own against this carom and runs its
# programs (gas_in_a_box, quick_start, tour): the two ways another project
# uses carom. The docs' C++ and CMake blocks are parts of these files
# (python/tests/test_docs.py checks it).
#   -DMODE=installed     `cmake --install` this build into WORK, then find_package(carom)
#   -DMODE=subdirectory  add_subdirectory(SOURCE)
#   -DSOURCE=<carom source> -DCAROM_BUILD=<this build> -DWORK=<scratch folder> -DCXX=<compiler> [-DLAUNCHER=ccache]
#   [-DPREFIX_PATH=<this build's CMAKE_PREFIX_PATH, where carom's own dependencies were found>]
#   [-DMPIEXEC=<mpiexec and its flags>: decomposed_gas runs on 1 and 3 processes, with the same output]
file(REMOVE_RECURSE "${WORK}")
function(run)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT status EQUAL 0)
        message(FATAL_ERROR "failed (${status}): ${ARGN}\n${out}${err}")
    endif()
    set(output "${out}${err}" PARENT_SCOPE)
endfunction()
# The prefix path is a list: it goes in through an initial cache file, where
# its semicolons stay one value.
if(MODE STREQUAL "installed")
    run(${CMAKE_COMMAND} --install "${CAROM_BUILD}" --prefix "${WORK}/prefix")
    set(prefixes "${WORK}/prefix;${PREFIX_PATH}")
    set(use_carom "")
elseif(MODE STREQUAL "subdirectory")
    set(prefixes "${PREFIX_PATH}")
    set(use_carom "-DCAROM_SOURCE_DIR=${SOURCE}")
else()
    message(FATAL_ERROR "MODE must be installed or subdirectory, got '${MODE}'")
endif()
file(WRITE "${WORK}/initial-cache.cmake" "set(CMAKE_PREFIX_PATH [==[${prefixes}]==] CACHE STRING \"\")\n")
run(${CMAKE_COMMAND} -C "${WORK}/initial-cache.cmake" -S "${SOURCE}/examples" -B "${WORK}/build"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}" ${use_carom})
run(${CMAKE_COMMAND} --build "${WORK}/build" -j2)
run("${WORK}/build/gas_in_a_box")
message("${output}")
# The pairwise scheme keeps the energy to float rounding over the 1000 steps.
if(NOT output MATCHES "relative energy change ([+-][0-9.]+e-(0[5-9]|[1-9][0-9])|[+-]0\\.00e\\+00)")
    message(FATAL_ERROR "the energy changed by 1e-4 or more")
endif()
run("${WORK}/build/quick_start")
message("${output}")
if(NOT output MATCHES "^kinetic energy (499\\.9|500)[0-9.]* \\(started at 500\\)")
    message(FATAL_ERROR "quick_start did not print the energy of 1000 disks")
endif()
# The tour writes its files into WORK; carom::io is there when carom found toml++.
if(EXISTS "${WORK}/build/tour")
    execute_process(COMMAND "${WORK}/build/tour" "${SOURCE}/scenes/mixture.toml" WORKING_DIRECTORY "${WORK}"
                    RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
    message("${out}${err}")
    if(NOT status EQUAL 0 OR NOT out MATCHES "resumed from the checkpoint: the same bits")
        message(FATAL_ERROR "tour failed (${status})")
    endif()
endif()
# A world split among MPI processes prints what one process prints.
if(EXISTS "${WORK}/build/decomposed_gas" AND MPIEXEC)
    foreach(processes IN ITEMS 1 3)
        run(${MPIEXEC} -np ${processes} "${WORK}/build/decomposed_gas")
        message("${processes} processes: ${output}")
        set(printed${processes} "${output}")
    endforeach()
    if(NOT printed1 MATCHES "step 200: 4000 disks among the processes\nkinetic energy" OR NOT printed1 STREQUAL printed3)
        message(FATAL_ERROR "decomposed_gas printed different results on 1 and 3 processes")
    endif()
endif()
