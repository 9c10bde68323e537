# Folders are floors: each file may include headers of its own floor and of
# the floors below it, never of one above. The floors, from the bottom:
#   0  the public definitions every floor speaks (include/carom/types.h, random.h, version.h)
#   1  kernels/     physics compiled for the host and for OpenCL devices
#   2  engine/      the core every backend shares (grid builder, checks, placement, observables)
#   3  backends/    the Backend interface and its implementations (backends/opencl/ included;
#                   include/carom/decomposition.h, whose decomposed world is one)
#   4  world/       carom::World and the backend factory (include/carom/world.h, carom.h)
#   5  io/          carom::io, the files (include/carom/io.h, files.h)
#   6  app/ python/ web/  the carom program, the Python package and the browser page
#   7  tests/ examples/ bench/ docs/
# A file of a folder not listed fails the test: a new floor is placed here first.
# Beyond the floors, carom::io is a client of the public API: files of io/
# may include include/carom/, io/ and the core's helpers in engine/ (and
# kernels/ below them), never world/ or backends/.
#   cmake -DSOURCE=<repository> -P floors.cmake
cmake_minimum_required(VERSION 3.21)
set(floor_patterns
    "^include/carom/(types|random|version)\\.h(\\.in)?$" 0
    "^kernels/" 1
    "^engine/" 2
    "^backends/" 3 "^include/carom/decomposition\\.h$" 3
    "^world/" 4 "^include/carom/(world|carom)\\.h$" 4
    "^io/" 5 "^include/carom/(io|files)\\.h$" 5
    "^(app|python|web)/" 6
    "^(tests|examples|bench|docs)/" 7)
# Pairs of a folder and the folders below it that its files must not include.
set(excluded_patterns "^io/" "^(world|backends)/")
function(floor_of path out)
    set(patterns ${floor_patterns})
    while(patterns)
        list(POP_FRONT patterns pattern floor)
        if(path MATCHES "${pattern}")
            set(${out} ${floor} PARENT_SCOPE)
            return()
        endif()
    endwhile()
    set(${out} "" PARENT_SCOPE)
endfunction()

execute_process(COMMAND git ls-files "*.h" "*.hpp" "*.c" "*.cpp" "*.cl" "*.inl" "*.h.in" WORKING_DIRECTORY "${SOURCE}"
                OUTPUT_VARIABLE tracked RESULT_VARIABLE listed OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT listed EQUAL 0 OR NOT tracked)
    # Not a git checkout (an unpacked archive): every source file under the folders above.
    file(GLOB_RECURSE tracked LIST_DIRECTORIES false RELATIVE "${SOURCE}" "${SOURCE}/*.h" "${SOURCE}/*.c"
         "${SOURCE}/*.cpp" "${SOURCE}/*.cl" "${SOURCE}/*.inl" "${SOURCE}/*.h.in")
    list(FILTER tracked EXCLUDE REGEX "^(build|\\.venv|\\.device-deps)")
else()
    string(REPLACE "\n" ";" tracked "${tracked}")
endif()

set(offenders "")
set(count 0)
foreach(name IN LISTS tracked)
    floor_of("${name}" own)
    if(own STREQUAL "")
        string(APPEND offenders "\n  ${name}: its folder is on no floor (tests/floors.cmake lists them)")
        continue()
    endif()
    math(EXPR count "${count} + 1")
    get_filename_component(folder "${name}" DIRECTORY)
    file(STRINGS "${SOURCE}/${name}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"][^>\"]+[>\"]")
    foreach(line IN LISTS includes)
        string(REGEX REPLACE "^[^<\"]*[<\"]([^>\"]+)[>\"].*" "\\1" included "${line}")
        # Resolved as the compilers do: beside the file, from the repository root, from include/.
        set(target "")
        foreach(candidate "${folder}/${included}" "${included}" "include/${included}")
            if(EXISTS "${SOURCE}/${candidate}" AND NOT IS_DIRECTORY "${SOURCE}/${candidate}")
                set(target "${candidate}")
                break()
            endif()
        endforeach()
        if(target STREQUAL "" AND included STREQUAL "carom/version.h")
            set(target "include/carom/version.h.in")  # written by CMake from the template
        endif()
        if(target STREQUAL "")
            continue()  # a system or third-party header
        endif()
        file(REAL_PATH "${SOURCE}/${target}" resolved)
        file(RELATIVE_PATH target "${SOURCE}" "${resolved}")
        floor_of("${target}" theirs)
        if(theirs STREQUAL "")
            string(APPEND offenders "\n  ${name}: includes ${target}, which is on no floor")
        elseif(theirs GREATER own)
            string(APPEND offenders "\n  ${name} (floor ${own}) includes ${target} (floor ${theirs})")
        endif()
        set(excluded ${excluded_patterns})
        while(excluded)
            list(POP_FRONT excluded folder_pattern target_pattern)
            if(name MATCHES "${folder_pattern}" AND target MATCHES "${target_pattern}")
                string(APPEND offenders "\n  ${name} includes ${target}: carom::io uses only the public API "
                                        "(include/carom/) and the core's helpers (engine/)")
            endif()
        endwhile()
    endforeach()
endforeach()
if(offenders)
    message(FATAL_ERROR "includes that run up a floor, or that io/ must not make:${offenders}")
endif()
message(STATUS "${count} files: every include runs down a floor or stays on its own")
