# Runs `carom view` headless under Xvfb (Mesa's software OpenGL) into a clean
# output folder: -DCAROM=<binary> -DOUT_DIR=<folder> -DARGS=a|b|c, and checks
# its output against -DOUTPUT_REGEX=<regex> when given. With
# -DSTOP_SIGNAL=TERM -DSTOP_AFTER=<seconds>, `timeout` sends carom that signal
# then; -DEXPECT_STATUS=<status> (default 0) and -DEXPECT_FILE=<file in
# OUT_DIR> check how it ended. With -DREFERENCE_ARGS=a|b|c, `carom a b c`
# runs first (no display needed) and must write reference.csv, and the
# view.csv the viewer writes must equal it byte for byte.
file(REMOVE_RECURSE "${OUT_DIR}")
file(MAKE_DIRECTORY "${OUT_DIR}")
find_program(XVFB_RUN xvfb-run REQUIRED)
if(REFERENCE_ARGS)
    string(REPLACE "|" ";" reference_args "${REFERENCE_ARGS}")
    execute_process(COMMAND ${CAROM} ${reference_args} WORKING_DIRECTORY "${OUT_DIR}" RESULT_VARIABLE status
                    ERROR_VARIABLE err OUTPUT_QUIET)
    if(NOT status EQUAL 0)
        message(FATAL_ERROR "the reference run `carom ${reference_args}` ended with status ${status}: ${err}")
    endif()
endif()
string(REPLACE "|" ";" args "${ARGS}")
set(stop)
if(STOP_SIGNAL)
    find_program(TIMEOUT timeout REQUIRED)
    set(stop ${TIMEOUT} --preserve-status -s ${STOP_SIGNAL} ${STOP_AFTER})
endif()
if(NOT DEFINED EXPECT_STATUS)
    set(EXPECT_STATUS 0)
endif()
# carom's own status, printed inside xvfb-run: xvfb-run exits 5 instead when
# removing its temporary folder fails as Xvfb shuts down, a race of its own.
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1920x1200x24"
                        sh -c "\"$@\"; echo \"carom exited with status $?\" >&2" sh ${stop} ${CAROM} ${args}
                WORKING_DIRECTORY "${OUT_DIR}" RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(err MATCHES "carom exited with status ([0-9]+)")
    set(status ${CMAKE_MATCH_1})
endif()
if(NOT status EQUAL EXPECT_STATUS)
    message(FATAL_ERROR "carom view ended with status ${status}, expected ${EXPECT_STATUS}")
endif()
if(OUTPUT_REGEX AND NOT "${out}${err}" MATCHES "${OUTPUT_REGEX}")
    message(FATAL_ERROR "output does not match '${OUTPUT_REGEX}'")
endif()
if(EXPECT_FILE AND NOT EXISTS "${OUT_DIR}/${EXPECT_FILE}")
    message(FATAL_ERROR "carom view did not write ${EXPECT_FILE}")
endif()
if(REFERENCE_ARGS)
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${OUT_DIR}/view.csv" "${OUT_DIR}/reference.csv"
                    RESULT_VARIABLE differ)
    if(NOT differ EQUAL 0)
        file(READ "${OUT_DIR}/view.csv" view_state)
        file(READ "${OUT_DIR}/reference.csv" reference_state)
        message(FATAL_ERROR "the viewer's final state view.csv:\n${view_state}differs from `carom ${reference_args}`'s "
                            "reference.csv:\n${reference_state}")
    endif()
endif()
