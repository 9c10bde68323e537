# Runs carom with ARGS ('|'-separated) and checks its exit status and output.
#   -DCAROM=<binary> -DARGS=run|--dt|0 -DEXPECT=fail|pass -DOUTPUT_REGEX=<regex>
#   [-DENV=NAME=VALUE] [-DABSENT_FILE=<path that must not exist afterwards>]
string(REPLACE "|" ";" args "${ARGS}")
if(ABSENT_FILE)
    file(REMOVE "${ABSENT_FILE}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env ${ENV} ${CAROM} ${args}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
if(EXPECT STREQUAL "fail" AND status EQUAL 0)
    message(FATAL_ERROR "expected a non-zero exit, got 0; output:\n${all}")
elseif(EXPECT STREQUAL "pass" AND NOT status EQUAL 0)
    message(FATAL_ERROR "expected exit 0, got ${status}; output:\n${all}")
endif()
if(NOT all MATCHES "${OUTPUT_REGEX}")
    message(FATAL_ERROR "output does not match '${OUTPUT_REGEX}':\n${all}")
endif()
if(ABSENT_FILE AND EXISTS "${ABSENT_FILE}")
    message(FATAL_ERROR "${ABSENT_FILE} was written although the run failed")
endif()
if(ABSENT_FILE AND EXISTS "${ABSENT_FILE}.partial")
    message(FATAL_ERROR "${ABSENT_FILE}.partial was left behind")
endif()
