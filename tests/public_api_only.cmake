# The carom program uses only the public API: no file of app/, and no
# app/bench/ header that the rest of app/ includes (directly or through
# another), may include the library's internal headers (kernels/, engine/,
# backends/, world/, io/). The rest of app/bench/ may: it implements the
# all-pairs baselines, the kernel profiles and the bandwidth probe, which
# exist only in the benchmark.
#   cmake -DSOURCE=<repository> -P public_api_only.cmake
cmake_minimum_required(VERSION 3.21)
file(GLOB_RECURSE pending LIST_DIRECTORIES false RELATIVE "${SOURCE}" "${SOURCE}/app/*.cpp" "${SOURCE}/app/*.h")
if(NOT pending)
    message(FATAL_ERROR "no files found under ${SOURCE}/app: give -DSOURCE=<the repository>")
endif()
list(FILTER pending EXCLUDE REGEX "^app/bench/")
set(checked "")
set(offenders "")
while(pending)
    list(POP_FRONT pending name)
    list(APPEND checked "${name}")
    file(STRINGS "${SOURCE}/${name}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"](kernels|engine|backends|world|io|app/bench)/")
    foreach(line IN LISTS includes)
        string(REGEX REPLACE ".*[<\"]([^>\"]+)[>\"].*" "\\1" included "${line}")
        if(NOT EXISTS "${SOURCE}/${included}")
            continue()  # another project's header of the same folder name (Dear ImGui's backends/)
        endif()
        if(included MATCHES "^app/bench/")
            if(NOT included IN_LIST checked AND NOT included IN_LIST pending)
                list(APPEND pending "${included}")
            endif()
        else()
            string(APPEND offenders "\n  ${name}: ${line}")
        endif()
    endforeach()
endwhile()
list(LENGTH checked count)
if(offenders)
    message(FATAL_ERROR "the carom program must use only the public API (include/carom/); these include internal headers:${offenders}")
endif()
message(STATUS "${count} files of the carom program (app/, and the app/bench/ headers it includes) use only the public API")
