# The browser build (`emcmake cmake`): included by the top-level CMakeLists.txt.

# carom reports bad input as carom::Error: WebAssembly's own exceptions
# (Chromium 95+, Firefox 100+, Safari 15.2+) catch them without the cost
# JavaScript-emulated ones add to every call in the stepping loops.
add_compile_options(-fwasm-exceptions)
add_link_options(-fwasm-exceptions)

# toml++ is header-only, but its CMake package puts the host's /usr/include,
# and with it the host's C library, on the include path. Only its own folder
# is linked into the build tree.
find_path(CAROM_TOMLPLUSPLUS_INCLUDE toml++/toml.h PATHS /usr/include /usr/local/include /opt/homebrew/include
          NO_CMAKE_FIND_ROOT_PATH)
if(NOT CAROM_TOMLPLUSPLUS_INCLUDE)
    message(FATAL_ERROR "the browser build reads scene files with toml++ (Debian: libtomlplusplus-dev)")
endif()
file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/tomlplusplus)
file(CREATE_LINK ${CAROM_TOMLPLUSPLUS_INCLUDE}/toml++ ${PROJECT_BINARY_DIR}/tomlplusplus/toml++ SYMBOLIC)
add_library(tomlplusplus::tomlplusplus INTERFACE IMPORTED)
target_include_directories(tomlplusplus::tomlplusplus INTERFACE ${PROJECT_BINARY_DIR}/tomlplusplus)

# emcc's JavaScript tools need Debian's acorn (node-acorn), which a node
# from elsewhere than Debian (NodeSource's) finds only on NODE_PATH.
set(CMAKE_CXX_LINKER_LAUNCHER ${CMAKE_COMMAND} -E env NODE_PATH=/usr/share/nodejs)
