# The viewer's headless runs stopped by a signal (issue 11, items 3 and 9).
# `carom run`'s signals and output failures are tested by outputs_test.py.
if(NOT CAROM_HAVE_VIEWER OR WIN32)
    return()
endif()

# A headless view stopped by SIGTERM or SIGINT after 3 s (of 10^8 frames): it
# writes the screenshot of the last frame it rendered, says how many that was,
# and exits 128 + the signal.
set(lifecycle_view "view|--backend|cpu|--particles|200|--window|200|200|--frames|100000000|--screenshot|last.png")
foreach(stop_status IN ITEMS TERM:143 INT:130)
    string(REPLACE ":" ";" stop_status ${stop_status})
    list(GET stop_status 0 stop)
    list(GET stop_status 1 status)
    add_test(NAME view.interrupted_writes_the_last_frame_${stop}
             COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DOUT_DIR=${CMAKE_CURRENT_BINARY_DIR}/view/stop-${stop}
                     "-DARGS=${lifecycle_view}" -DSTOP_SIGNAL=${stop} -DSTOP_AFTER=3 -DEXPECT_STATUS=${status}
                     -DEXPECT_FILE=last.png
                     "-DOUTPUT_REGEX=carom view: [0-9]+ frames of 200 disks.*interrupted by SIG${stop} after [0-9]+ of 100000000 frames; last.png shows frame [0-9]+, the last rendered"
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/run_viewer.cmake)
    set_tests_properties(view.interrupted_writes_the_last_frame_${stop} PROPERTIES TIMEOUT 120 RESOURCE_LOCK xvfb)
endforeach()
