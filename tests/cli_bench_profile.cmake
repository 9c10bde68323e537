# `carom bench --profile` under the pairwise scheme at N = PARTICLES: every part in PARTS has a
# time > 0 in the profile of the method's row.
#   cmake -DCAROM=<binary> -DJSON=<file> -DMETHODS=<method> -DPARTICLES=<N> -DPARTS=a|b|c -P cli_bench_profile.cmake
file(REMOVE ${JSON})
execute_process(COMMAND ${CAROM} bench --methods ${METHODS} --collisions pairwise --sizes ${PARTICLES} --samples 1 --profile
                        --json ${JSON}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "carom bench failed (${status}):\n${out}${err}")
endif()
file(READ ${JSON} text)
string(JSON scheme GET "${text}" results 0 scheme)
string(JSON profile GET "${text}" results 0 profile_ms_per_step)
if(NOT scheme STREQUAL "pairwise")
    message(FATAL_ERROR "expected a pairwise row, got '${scheme}':\n${text}")
endif()
string(REPLACE "|" ";" parts "${PARTS}")
foreach(part IN LISTS parts)
    string(JSON ms ERROR_VARIABLE missing GET "${profile}" "${part}")
    if(missing OR NOT ms GREATER 0)
        message(FATAL_ERROR "the profile has no time for '${part}':\n${profile}")
    endif()
endforeach()
