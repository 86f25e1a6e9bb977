# SPDX-License-Identifier: LGPL-2.1-only
# The 2.x-ABI custom filter the benchmark loads: tests/compat/ext/ext_passthrough_variable.c built
# against include/nnstreamer and linked to libnnstreamer-single.so, as an extension is.
add_library(nns_bench_ext_passthrough MODULE
            ${CMAKE_SOURCE_DIR}/tests/compat/ext/ext_passthrough_variable.c)
set_target_properties(nns_bench_ext_passthrough PROPERTIES PREFIX "lib"
  OUTPUT_NAME "bench_ext_passthrough" LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bench)
target_include_directories(nns_bench_ext_passthrough PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
target_link_libraries(nns_bench_ext_passthrough PRIVATE nnstreamer-single PkgConfig::GST
                      nns_warnings)
add_dependencies(${name} nns_bench_ext_passthrough)
target_compile_definitions(${name} PRIVATE
  NNS_BENCH_EXT_FILTER="$<TARGET_FILE:nns_bench_ext_passthrough>")
