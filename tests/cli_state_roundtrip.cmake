# carom run --output-state, then --input-state of that file for 0 steps:
# the two files must be identical (9 significant digits read back exactly).
set(dir "${WORK_DIR}/roundtrip")
file(MAKE_DIRECTORY "${dir}")
foreach(step IN ITEMS
        "run;--backend;cpu;--particles;300;--box;60;60;--radius-min;0.5;--radius-max;1.5;--mass-min;0.1;--mass-max;7;--steps;50;--output-state;${dir}/first.csv"
        "run;--backend;cpu;--input-state;${dir}/first.csv;--box;60;60;--steps;0;--output-state;${dir}/second.csv")
    execute_process(COMMAND ${CAROM} ${step} RESULT_VARIABLE status ERROR_VARIABLE err OUTPUT_QUIET)
    if(NOT status EQUAL 0)
        message(FATAL_ERROR "carom ${step} failed: ${err}")
    endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${dir}/first.csv" "${dir}/second.csv" RESULT_VARIABLE differ)
if(differ)
    message(FATAL_ERROR "the state read back from first.csv was written differently")
endif()
