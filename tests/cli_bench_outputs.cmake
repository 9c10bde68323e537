# `carom bench` writes its JSON, CSV and SVG plot, each with one entry per
# method, scheme and N measured: naive-cpu under the simultaneous scheme, cpu
# under both stepped schemes, events under the events scheme (the default: all),
# at two N. The events rows have rates, not step times, and no line in the plot.
#   cmake -DCAROM=<binary> -DWORK_DIR=<dir> -P cli_bench_outputs.cmake
set(json ${WORK_DIR}/bench-outputs.json)
set(csv ${WORK_DIR}/bench-outputs.csv)
set(svg ${WORK_DIR}/bench-outputs.svg)
file(REMOVE ${json} ${csv} ${svg})
execute_process(COMMAND ${CAROM} bench --methods cpu,naive-cpu,events --sizes 100,300 --samples 1 --json ${json}
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
if(NOT rows EQUAL 8 OR NOT rate GREATER 0 OR NOT bandwidth GREATER 0)
    message(FATAL_ERROR "unexpected JSON: ${rows} rows, rate ${rate}, bandwidth ${bandwidth}:\n${text}")
endif()
# Rows by N, then method, then scheme: naive-cpu, cpu, cpu pairwise, events;
# only the pairwise row has a pairwise/simultaneous ratio.
foreach(row 0 1 2)
    string(JSON method GET "${results}" ${row} method)
    string(JSON scheme GET "${results}" ${row} scheme)
    string(JSON ratio GET "${results}" ${row} pairwise_over_simultaneous)
    list(APPEND seen "${method}/${scheme}/${ratio}")
endforeach()
if(NOT seen MATCHES "^naive-cpu/simultaneous/;cpu/simultaneous/;cpu/pairwise/[0-9]")
    message(FATAL_ERROR "unexpected rows (method/scheme/pairwise_over_simultaneous): ${seen}\n${text}")
endif()
# The CPU engines hold nothing on a device.
string(JSON deviceBytes GET "${results}" 1 device_bytes_per_particle)
if(NOT deviceBytes EQUAL 0)
    message(FATAL_ERROR "the cpu method's device_bytes_per_particle is ${deviceBytes}, not 0:\n${text}")
endif()
# The events row: its rates (events of every kind include the collisions), the
# warm-up off the lattice (TimingPlan::warmupCollisionsPerDisk) and the counts
# behind them; no step time.
string(JSON method GET "${results}" 3 method)
string(JSON scheme GET "${results}" 3 scheme)
string(JSON boundary GET "${results}" 3 boundary)
string(JSON collisionRate GET "${results}" 3 collisions_per_second)
string(JSON eventRate GET "${results}" 3 events_per_second)
string(JSON particleTime GET "${results}" 3 particle_time_per_second)
string(JSON warmup GET "${results}" 3 warmup_collisions_per_disk)
string(JSON crossings GET "${results}" 3 sampled_events cell_crossings)
string(JSON stepTime ERROR_VARIABLE noStepTime GET "${results}" 3 ms_per_step)
if(NOT method STREQUAL "events" OR NOT scheme STREQUAL "events" OR NOT boundary STREQUAL "periodic"
   OR NOT collisionRate GREATER 0 OR eventRate LESS collisionRate OR NOT particleTime GREATER 0
   OR warmup LESS 3 OR NOT crossings GREATER 0 OR NOT noStepTime)
    message(FATAL_ERROR "unexpected events row: ${method}/${scheme}/${boundary}, ${collisionRate} collisions/s, "
                        "${eventRate} events/s, ${particleTime} particle-time/s, ${warmup} warm-up collisions "
                        "per disk, ${crossings} crossings, ms_per_step ${stepTime}:\n${text}")
endif()

file(STRINGS ${csv} lines)
list(LENGTH lines count)
list(GET lines 0 header)
list(GET lines 3 pairwiseRow)
list(GET lines 4 eventsRow)
if(NOT count EQUAL 9 OR NOT header MATCHES "^method,particles,ms_per_step,particle_steps_per_second,.*,scheme,pairwise_over_simultaneous,collisions_per_second,particle_time_per_second,events_per_second$"
   OR NOT pairwiseRow MATCHES "^cpu,100,.*,pairwise,[0-9.e+-]+,,,$"
   OR NOT eventsRow MATCHES "^events,100,,,,,,,1,[0-9]+,events,,[0-9.e+]+,[0-9.e+]+,[0-9.e+]+$")
    message(FATAL_ERROR "unexpected CSV (${count} lines):\n${lines}")
endif()

file(READ ${svg} plot)
if(NOT plot MATCHES "^<svg " OR NOT plot MATCHES "<polyline[^>]*points=" OR NOT plot MATCHES "naive-cpu"
   OR NOT plot MATCHES ">cpu pairwise<" OR plot MATCHES ">events")
    message(FATAL_ERROR "unexpected SVG:\n${plot}")
endif()
