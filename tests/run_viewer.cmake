# Runs `carom view` headless under Xvfb (Mesa's software OpenGL) into a clean
# output folder: -DCAROM=<binary> -DOUT_DIR=<folder> -DARGS=a|b|c, and checks
# its output against -DOUTPUT_REGEX=<regex> when given. With
# -DSTOP_SIGNAL=TERM -DSTOP_AFTER=<seconds>, `timeout` sends carom that signal
# then; -DEXPECT_STATUS=<status> (default 0) and -DEXPECT_FILE=<file in
# OUT_DIR> check how it ended.
file(REMOVE_RECURSE "${OUT_DIR}")
file(MAKE_DIRECTORY "${OUT_DIR}")
find_program(XVFB_RUN xvfb-run REQUIRED)
string(REPLACE "|" ";" args "${ARGS}")
set(stop)
if(STOP_SIGNAL)
    find_program(TIMEOUT timeout REQUIRED)
    set(stop ${TIMEOUT} --preserve-status -s ${STOP_SIGNAL} ${STOP_AFTER})
endif()
if(NOT DEFINED EXPECT_STATUS)
    set(EXPECT_STATUS 0)
endif()
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1024x768x24" ${stop} ${CAROM} ${args}
                WORKING_DIRECTORY "${OUT_DIR}" RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT status EQUAL EXPECT_STATUS)
    message(FATAL_ERROR "carom view ended with status ${status}, expected ${EXPECT_STATUS}")
endif()
if(OUTPUT_REGEX AND NOT "${out}${err}" MATCHES "${OUTPUT_REGEX}")
    message(FATAL_ERROR "output does not match '${OUTPUT_REGEX}'")
endif()
if(EXPECT_FILE AND NOT EXISTS "${OUT_DIR}/${EXPECT_FILE}")
    message(FATAL_ERROR "carom view did not write ${EXPECT_FILE}")
endif()
