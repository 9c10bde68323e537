# `carom view`: headless renders under Xvfb with Mesa's software OpenGL,
# checked pixel by pixel by view_check.cpp; and the refusals.
if(NOT CAROM_HAVE_VIEWER)
    return()
endif()
find_path(STB_IMAGE_DIR stb/stb_image.h REQUIRED)

add_executable(carom_view_check view_check.cpp ${PROJECT_SOURCE_DIR}/app/viewer/renderer.cpp)
target_include_directories(carom_view_check PRIVATE ${PROJECT_SOURCE_DIR} ${PROJECT_SOURCE_DIR}/include ${STB_IMAGE_DIR})
target_link_libraries(carom_view_check PRIVATE doctest::doctest OpenGL::GL ${STB_LIBRARY})

set(view_out ${CMAKE_CURRENT_BINARY_DIR}/view)
set(view_scene "view|--backend|cpu|--input-state|${CMAKE_CURRENT_SOURCE_DIR}/data/view_disks.csv|--box|100|50|--window|400|300|--hide-panels|--color|id")
add_test(NAME view.screenshot
         COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DOUT_DIR=${view_out}/screenshot
                 "-DARGS=${view_scene}|--frames|1|--screenshot|view.png" -P ${CMAKE_CURRENT_SOURCE_DIR}/run_viewer.cmake)
add_test(NAME view.record
         COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DOUT_DIR=${view_out}/record
                 "-DARGS=${view_scene}|--frames|5|--record|frames" -P ${CMAKE_CURRENT_SOURCE_DIR}/run_viewer.cmake)
# The panels drawn under gravity with the pairwise scheme: the viewer runs the scheme asked for, and the total
# energy (kinetic plus potential) it reports drifts by less than 1e-4 relative over the 80 steps.
add_test(NAME view.pairwise_gravity
         COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DOUT_DIR=${view_out}/pairwise
                 "-DARGS=view|--backend|cpu|--particles|300|--gravity|0|-1|--collisions|pairwise|--window|400|300|--frames|20"
                 "-DOUTPUT_REGEX=pairwise collisions, total energy drift [+-][0-9.]+e-(0[5-9]|[1-9][0-9]) over 0.8 time units"
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/run_viewer.cmake)
# Two xvfb-run -a at once race for a display number and for their temporary
# folder (status 5, "problem while cleaning up"): one Xvfb test at a time.
set_tests_properties(view.screenshot view.record view.pairwise_gravity PROPERTIES RESOURCE_LOCK xvfb)
set_tests_properties(view.screenshot PROPERTIES FIXTURES_SETUP view_screenshot)
set_tests_properties(view.record PROPERTIES FIXTURES_SETUP view_record)
add_test(NAME view.check_screenshot COMMAND carom_view_check -tc=screenshot*)
add_test(NAME view.check_record COMMAND carom_view_check -tc=record*)
set_tests_properties(view.check_screenshot PROPERTIES FIXTURES_REQUIRED view_screenshot ENVIRONMENT CAROM_VIEW_OUTPUT=${view_out})
set_tests_properties(view.check_record PROPERTIES FIXTURES_REQUIRED view_record ENVIRONMENT CAROM_VIEW_OUTPUT=${view_out})

# The layout with the panels shown (issue 16), at the smallest window it is made for, a square one and the
# default: disks at the four corners and the centre of a 100 x 100 box show where the camera puts them, in the
# view the panel column leaves free.
foreach(size IN ITEMS 320x240 400x400 1280x800)
    string(REPLACE "x" "|" window ${size})
    add_test(NAME view.layout_${size}
             COMMAND ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DOUT_DIR=${view_out}/layout_${size}
                     "-DARGS=view|--backend|cpu|--input-state|${CMAKE_CURRENT_SOURCE_DIR}/data/view_corners.csv|--box|100|100|--window|${window}|--color|id|--frames|2|--screenshot|view.png"
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/run_viewer.cmake)
    set_tests_properties(view.layout_${size} PROPERTIES RESOURCE_LOCK xvfb FIXTURES_SETUP view_layout_${size})
    add_test(NAME view.check_layout_${size} COMMAND carom_view_check "-tc=layout ${size}:*")
    set_tests_properties(view.check_layout_${size} PROPERTIES FIXTURES_REQUIRED view_layout_${size}
                                                              ENVIRONMENT CAROM_VIEW_OUTPUT=${view_out})
endforeach()
# The camera's arithmetic with the panels shown, collapsed and hidden, zoomed and panned: no display needed.
add_test(NAME view.camera COMMAND carom_view_check -tc=camera*)

carom_cli_test(view_without_display fail "carom view needs a display" "view|--backend|cpu" DISPLAY=)
carom_cli_test(view_bad_window fail "--window 10 10: each side must be in \\[64, 16384\\] pixels" "view|--window|10|10")
carom_cli_test(view_bad_colouring fail "--color 'rainbow' is not a colouring" "view|--color|rainbow|--frames|1")
carom_cli_test(view_screenshot_needs_frames fail "--screenshot requires --frames" "view|--screenshot|x.png")
