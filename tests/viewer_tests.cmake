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
# view.NAME: `carom ARGS` (|-separated) headless under Xvfb, writing into ${view_out}/NAME; with a third
# argument, its output must match that regular expression (none if empty); with a fourth, REFERENCE, `carom
# REFERENCE` runs first and the view.csv the viewer writes must equal its reference.csv. One Xvfb test at a
# time: two xvfb-run -a at once race for a display number and for their temporary folder (status 5, "problem
# while cleaning up").
function(carom_view_test name args)
    set(command ${CMAKE_COMMAND} -DCAROM=$<TARGET_FILE:carom> -DOUT_DIR=${view_out}/${name} "-DARGS=${args}")
    if(ARGC GREATER 2)
        list(APPEND command "-DOUTPUT_REGEX=${ARGV2}")
    endif()
    if(ARGC GREATER 3)
        list(APPEND command "-DREFERENCE_ARGS=${ARGV3}")
    endif()
    add_test(NAME view.${name} COMMAND ${command} -P ${CMAKE_CURRENT_SOURCE_DIR}/run_viewer.cmake)
    set_tests_properties(view.${name} PROPERTIES RESOURCE_LOCK xvfb)
endfunction()
set(view_scene "view|--backend|cpu|--input-state|${CMAKE_CURRENT_SOURCE_DIR}/data/view_disks.csv|--box|100|50|--window|400|300|--hide-panels|--color|id")
carom_view_test(screenshot "${view_scene}|--frames|1|--screenshot|view.png")
carom_view_test(record "${view_scene}|--frames|5|--record|frames")
# The panels drawn under gravity with the pairwise scheme: the viewer runs the scheme asked for, and the total
# energy (kinetic plus potential) it reports drifts by less than 1e-4 relative over the 80 steps.
carom_view_test(pairwise_gravity
                "view|--backend|cpu|--particles|300|--gravity|0|-1|--collisions|pairwise|--window|400|300|--frames|20"
                "pairwise collisions, total energy drift [+-][0-9.]+e-(0[5-9]|[1-9][0-9]) over 0.8 time units")
# The collisions selector's live switch (--switch-collisions, as the panel does it): from the seed's scheme to
# pairwise halfway, under gravity. The summary names the new scheme, the drift restarts at the switch (0.84 time
# units of the 1.6) and stays below 1e-4 while kinetic energy grows and potential energy falls by as much.
carom_view_test(switch_collisions
                "view|--backend|cpu|--particles|300|--gravity|0|-1|--collisions|simultaneous|--window|400|300|--frames|40|--switch-collisions|20|pairwise"
                "pairwise collisions from here.*40 frames of 300 disks, pairwise collisions, total energy drift [+-][0-9.]+e-(0[5-9]|[1-9][0-9]) over 0.84 time units \\(kinetic \\+[1-9][0-9.]*, potential -[1-9][0-9.]*\\)")
# A switch the engine refuses (events with the substeps of --dt auto) is shown and the viewer runs on, unchanged.
carom_view_test(switch_refused
                "view|--backend|cpu|--particles|100|--dt|auto|--window|400|300|--frames|3|--switch-collisions|2|events"
                "the events scheme has no steps to split.*3 frames of 100 disks, pairwise collisions")
# A periodic box under gravity has no floor: -sum m g.x jumps whenever a disk wraps (the total "drifted" by
# +14.2 here), and the drift shown is the kinetic energy's in the centre-of-mass frame, which collisions conserve.
carom_view_test(periodic_gravity_drift
                "view|--backend|cpu|--particles|50|--packing|0.05|--boundary|periodic|--gravity|0|-300|--window|400|300|--frames|40"
                "pairwise collisions, kinetic energy in the centre-of-mass frame drift [+-](0\\.000[0-9]*|[0-9.]+e-(0[4-9]|[1-9][0-9])) over")
# Disks at rest without gravity have no energy: the relative drift is undefined and shown as such (it was -nan).
carom_view_test(zero_energy
                "view|--backend|cpu|--particles|50|--speed|0|--window|400|300|--frames|2"
                "total energy drift n/a \\(from 0, change \\+0\\)")
# --scene: the viewer's scene is the file's two groups (42 disks, not the 1000 of --particles' default), with the
# file's gravity: kinetic and potential energy trade while the total stays put.
carom_view_test(scene_groups
                "view|--backend|cpu|--scene|${CMAKE_CURRENT_SOURCE_DIR}/data/view_groups.toml|--window|400|300|--frames|20"
                "20 frames of 42 disks \\(the scene's groups: group\\[1\\] 'light' 30, group\\[2\\] 'heavy' 12\\), pairwise collisions, total energy drift [+-][0-9.]+e-(0[5-9]|[1-9][0-9]) over 0.8 time units \\(kinetic \\+[1-9][0-9.]*, potential -[1-9]")
# --color mass on equal masses: every disk takes viridis' middle stop, drawn by the vertex shader's colour map.
string(REPLACE "--color|id" "--color|mass" view_scene_mass "${view_scene}")
carom_view_test(screenshot_mass "${view_scene_mass}|--frames|1|--screenshot|view.png")
set_tests_properties(view.screenshot_mass PROPERTIES FIXTURES_SETUP view_screenshot_mass)
add_test(NAME view.check_screenshot_mass COMMAND carom_view_check "-tc=screenshot_mass:*")
set_tests_properties(view.check_screenshot_mass PROPERTIES FIXTURES_REQUIRED view_screenshot_mass
                     ENVIRONMENT CAROM_VIEW_OUTPUT=${view_out})
set_tests_properties(view.screenshot PROPERTIES FIXTURES_SETUP view_screenshot)
set_tests_properties(view.record PROPERTIES FIXTURES_SETUP view_record)
add_test(NAME view.check_screenshot COMMAND carom_view_check "-tc=screenshot:*")
# The same disks on the resident OpenCL pipeline (issue 16, the GPU path): the device writes their views in its
# cell order with their ids, and the picture must be the same.
if(OpenCL_FOUND)
    string(REPLACE "--backend|cpu" "--backend|opencl|--pipeline|resident" view_scene_resident "${view_scene}")
    # The output names the pipeline, so the test cannot pass on the CPU; the grid sorts the three disks by cell,
    # so the device's slots are not in id order (the check fails if the views' ids are the slots).
    carom_view_test(screenshot_resident "${view_scene_resident}|--frames|1|--screenshot|view.png"
                    "resident pipeline")
    set_tests_properties(view.screenshot_resident PROPERTIES FIXTURES_SETUP view_screenshot_resident)
    add_test(NAME view.check_screenshot_resident COMMAND carom_view_check "-tc=screenshot:*")
    set_tests_properties(view.check_screenshot_resident PROPERTIES FIXTURES_REQUIRED view_screenshot_resident
                         ENVIRONMENT "CAROM_VIEW_OUTPUT=${view_out};CAROM_VIEW_SCREENSHOT=screenshot_resident")
    # Its readouts come from the device's sums: pairwise under gravity, kinetic and potential energy trade while
    # the total drifts by less than 1e-4 relative, as on the CPU (view.pairwise_gravity).
    carom_view_test(pairwise_gravity_resident
                    "view|--backend|opencl|--pipeline|resident|--particles|300|--gravity|0|-1|--collisions|pairwise|--window|400|300|--frames|20"
                    "resident pipeline.*pairwise collisions, total energy drift [+-][0-9.]+e-(0[5-9]|[1-9][0-9]) over 0.8 time units \\(kinetic \\+[1-9][0-9.]*, potential -[1-9]")
endif()
add_test(NAME view.check_record COMMAND carom_view_check -tc=record*)
set_tests_properties(view.check_screenshot PROPERTIES FIXTURES_REQUIRED view_screenshot ENVIRONMENT CAROM_VIEW_OUTPUT=${view_out})
set_tests_properties(view.check_record PROPERTIES FIXTURES_REQUIRED view_record ENVIRONMENT CAROM_VIEW_OUTPUT=${view_out})

# The layout with the panels shown (issue 16), at the smallest window it is made for, a square one and the
# default: disks at the four corners and the centre of a 100 x 100 box show where the camera puts them, in the
# view the panel column leaves free.
foreach(size IN ITEMS 320x240 400x400 1280x800)
    string(REPLACE "x" "|" window ${size})
    carom_view_test(layout_${size}
                    "view|--backend|cpu|--input-state|${CMAKE_CURRENT_SOURCE_DIR}/data/view_corners.csv|--box|100|100|--window|${window}|--color|id|--frames|2|--screenshot|view.png")
    set_tests_properties(view.layout_${size} PROPERTIES FIXTURES_SETUP view_layout_${size})
    add_test(NAME view.check_layout_${size} COMMAND carom_view_check "-tc=layout ${size}:*")
    set_tests_properties(view.check_layout_${size} PROPERTIES FIXTURES_REQUIRED view_layout_${size}
                                                              ENVIRONMENT CAROM_VIEW_OUTPUT=${view_out})
endforeach()
# Interactions (issue 16): --events hands scripted keys, clicks, drags and wheel steps to the viewer's event
# handler before their frames, with the panels hidden so that the mouse reaches the box. On view_disks.csv (at
# rest): view.check_throw and view.check_burst read the final state (--output-state), view.check_zoom_pan the
# screenshot. On a moving scene, the final state must equal `carom run`'s after as many steps as the script lets
# the viewer take (4 a running frame, 1 for N).
carom_view_test(throw "${view_scene}|--frames|6|--events|${data}/view_throw.events|--output-state|view.csv")
carom_view_test(burst "${view_scene}|--frames|5|--events|${data}/view_burst.events|--output-state|view.csv"
                "5 frames of 15 disks")
carom_view_test(zoom_pan "${view_scene}|--frames|6|--events|${data}/view_zoom_pan.events|--screenshot|view.png")
# With --scene a burst's disks are the file's first group's (radius 2, mass 5), not the command line's.
carom_view_test(burst_scene
                "view|--backend|cpu|--scene|${data}/view_burst_scene.toml|--window|400|300|--hide-panels|--frames|5|--events|${data}/view_burst.events|--output-state|view.csv"
                "5 frames of 15 disks")
foreach(name IN ITEMS throw burst burst_scene zoom_pan)
    set_tests_properties(view.${name} PROPERTIES FIXTURES_SETUP view_${name})
    add_test(NAME view.check_${name} COMMAND carom_view_check "-tc=${name}:*")
    set_tests_properties(view.check_${name} PROPERTIES FIXTURES_REQUIRED view_${name}
                                                         ENVIRONMENT CAROM_VIEW_OUTPUT=${view_out})
endforeach()
set(view_moving "--backend|cpu|--particles|30|--box|20|20")
set(view_moving_window "view|${view_moving}|--window|200|200|--hide-panels|--frames|6|--output-state|view.csv")
# Paused before frame 3 and stepped once before frame 5: 2 x 4 + 1 steps.
carom_view_test(pause_step "${view_moving_window}|--events|${data}/view_pause_step.events" ""
                "run|${view_moving}|--steps|9|--output-state|reference.csv")
# Paused before frame 3 without N: 2 x 4 steps, however many frames follow.
carom_view_test(pause "${view_moving_window}|--events|${data}/view_pause.events" ""
                "run|${view_moving}|--steps|8|--output-state|reference.csv")
# A disk thrown, then R before frame 5: the initial state, then frames 5 and 6 run 8 steps from it.
carom_view_test(reset "${view_moving_window}|--events|${data}/view_reset.events" ""
                "run|${view_moving}|--steps|8|--output-state|reference.csv")

# The camera's arithmetic with the panels shown, collapsed and hidden, zoomed and panned: no display needed.
add_test(NAME view.camera COMMAND carom_view_check -tc=camera*)

carom_cli_test(view_without_display fail "carom view needs a display" "view|--backend|cpu" DISPLAY=)
carom_cli_test(view_bad_window fail "--window: '10' is out of range; allowed: whole numbers from 64 to 16384"
               "view|--window|10|10")
# A negative side is refused with the same range, not the parser's (0 to 2^31 - 1).
carom_cli_test(view_negative_window fail "--window: '-1' is out of range; allowed: whole numbers from 64 to 16384"
               "view|--window|-1|100")
carom_cli_test(view_negative_steps_per_frame fail
               "--steps-per-frame: '-1' is out of range; allowed: whole numbers from 0 to 100000"
               "view|--steps-per-frame|-1")
carom_cli_test(view_bad_colouring fail "--color 'rainbow' is not a colouring" "view|--color|rainbow|--frames|1")
carom_cli_test(view_bad_switch fail "unknown collision scheme 'bogus'" "view|--switch-collisions|1|bogus|--frames|1")
carom_cli_test(view_switch_after_last fail "--switch-collisions frame 9 is after the last one; allowed: 1 to --frames \\(3\\)"
               "view|--switch-collisions|9|pairwise|--frames|3")
carom_cli_test(view_events_folder fail "cannot read --events file '[^']*data': it is a directory"
               "view|--events|${CMAKE_CURRENT_SOURCE_DIR}/data|--frames|3")
carom_cli_test(view_bad_events fail
               "--events [^ ]*view_bad.events line 2 '2 press left 500 100': X '500' is out of range; allowed: whole numbers from 0 to 399"
               "view|--backend|cpu|--window|400|300|--frames|3|--events|${data}/view_bad.events")
# An --events file is read as every text input is: a line without end
# (/dev/zero) or a NUL byte is refused at once, and its text is shown escaped.
carom_cli_test(view_events_dev_zero fail "/dev/zero:1: line longer than 4096 bytes; in a --events file lines are at most"
               "view|--backend|cpu|--frames|1|--events|/dev/zero")
set_tests_properties(cli.view_events_dev_zero PROPERTIES TIMEOUT 60)
carom_cli_test(view_events_nul fail "view_nul.events:2: a NUL byte, which no text file has \\(is it a --events file\\?\\)"
               "view|--backend|cpu|--frames|3|--events|${data}/view_nul.events")
carom_cli_test(view_events_escape fail "line 2 '1 .x1B\\[2J 5': '.x1B\\[2J' is not an action"
               "view|--backend|cpu|--frames|3|--events|${data}/view_escape.events")
carom_cli_test(view_screenshot_needs_frames fail "--screenshot requires --frames" "view|--screenshot|x.png")
