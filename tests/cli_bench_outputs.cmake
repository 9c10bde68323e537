# `carom bench` writes its JSON, CSV and SVG plot, each with one entry per
# method, scheme and N measured: naive-cpu under the simultaneous scheme, cpu
# under both (the default), at two N.
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
if(NOT rows EQUAL 6 OR NOT rate GREATER 0 OR NOT bandwidth GREATER 0)
    message(FATAL_ERROR "unexpected JSON: ${rows} rows, rate ${rate}, bandwidth ${bandwidth}:\n${text}")
endif()
# Rows by N, then method, then scheme: naive-cpu, cpu, cpu pairwise; only the
# pairwise row has a pairwise/simultaneous ratio.
foreach(row 0 1 2)
    string(JSON method GET "${results}" ${row} method)
    string(JSON scheme GET "${results}" ${row} scheme)
    string(JSON ratio GET "${results}" ${row} pairwise_over_simultaneous)
    list(APPEND seen "${method}/${scheme}/${ratio}")
endforeach()
if(NOT seen MATCHES "^naive-cpu/simultaneous/;cpu/simultaneous/;cpu/pairwise/[0-9]")
    message(FATAL_ERROR "unexpected rows (method/scheme/pairwise_over_simultaneous): ${seen}\n${text}")
endif()

file(STRINGS ${csv} lines)
list(LENGTH lines count)
list(GET lines 0 header)
list(GET lines 3 pairwiseRow)
if(NOT count EQUAL 7 OR NOT header MATCHES "^method,particles,ms_per_step,particle_steps_per_second,.*,scheme,pairwise_over_simultaneous$"
   OR NOT pairwiseRow MATCHES "^cpu,100,.*,pairwise,[0-9]")
    message(FATAL_ERROR "unexpected CSV (${count} lines):\n${lines}")
endif()

file(READ ${svg} plot)
if(NOT plot MATCHES "^<svg " OR NOT plot MATCHES "<polyline[^>]*points=" OR NOT plot MATCHES "naive-cpu"
   OR NOT plot MATCHES ">cpu pairwise<")
    message(FATAL_ERROR "unexpected SVG:\n${plot}")
endif()
