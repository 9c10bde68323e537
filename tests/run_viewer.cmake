# Runs `carom view` headless under Xvfb (Mesa's software OpenGL) into a clean
# output folder: -DCAROM=<binary> -DOUT_DIR=<folder> -DARGS=a|b|c, and checks
# its output against -DOUTPUT_REGEX=<regex> when given.
file(REMOVE_RECURSE "${OUT_DIR}")
file(MAKE_DIRECTORY "${OUT_DIR}")
find_program(XVFB_RUN xvfb-run REQUIRED)
string(REPLACE "|" ";" args "${ARGS}")
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1024x768x24" ${CAROM} ${args}
                WORKING_DIRECTORY "${OUT_DIR}" RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT status EQUAL 0)
    message(FATAL_ERROR "carom view failed with status ${status}")
endif()
if(OUTPUT_REGEX AND NOT "${out}${err}" MATCHES "${OUTPUT_REGEX}")
    message(FATAL_ERROR "output does not match '${OUTPUT_REGEX}'")
endif()
