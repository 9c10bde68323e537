# `carom bench` writes its JSON, CSV and SVG plot, each with one entry per
# method and N measured.
#   cmake -DCAROM=<binary> -DWORK_DIR=<dir> -P cli_bench_outputs.cmake
set(json ${WORK_DIR}/bench-outputs.json)
set(csv ${WORK_DIR}/bench-outputs.csv)
set(svg ${WORK_DIR}/bench-outputs.svg)
file(REMOVE ${json} ${csv} ${svg})
execute_process(COMMAND ${CAROM} bench --methods cpu,naive-cpu --sizes 100,300 --samples 1 --json ${json}
                        --csv ${csv} --plot ${svg}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "carom bench failed (${status}):\n${out}${err}")
endif()

file(READ ${json} text)
string(JSON results GET "${text}" results)
string(JSON rows LENGTH "${results}")
string(JSON rate GET "${results}" 0 particle_steps_per_second)
string(JSON bandwidth GET "${text}" bandwidth_bytes_per_second host_copy)
if(NOT rows EQUAL 4 OR NOT rate GREATER 0 OR NOT bandwidth GREATER 0)
    message(FATAL_ERROR "unexpected JSON: ${rows} rows, rate ${rate}, bandwidth ${bandwidth}:\n${text}")
endif()

file(STRINGS ${csv} lines)
list(LENGTH lines count)
list(GET lines 0 header)
if(NOT count EQUAL 5 OR NOT header MATCHES "^method,particles,ms_per_step,particle_steps_per_second,")
    message(FATAL_ERROR "unexpected CSV (${count} lines):\n${lines}")
endif()

file(READ ${svg} plot)
if(NOT plot MATCHES "^<svg " OR NOT plot MATCHES "<polyline[^>]*points=" OR NOT plot MATCHES "naive-cpu")
    message(FATAL_ERROR "unexpected SVG:\n${plot}")
endif()
