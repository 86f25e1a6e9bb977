# SPDX-License-Identifier: LGPL-2.1-only
# The NNStreamer 2.x-ABI filters subplugin2x_bench measures, built into build/bench/2x/.
foreach(m custom_pass subplugin_pass)
  add_library(nns_bench2x_${m} MODULE ${CMAKE_CURRENT_SOURCE_DIR}/compat2x/${m}.c)
  target_include_directories(nns_bench2x_${m} PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
  target_link_libraries(nns_bench2x_${m} PRIVATE nns_warnings)
  set_target_properties(nns_bench2x_${m} PROPERTIES PREFIX "lib"
                        LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bench/2x)
  add_dependencies(${name} nns_bench2x_${m})
endforeach()
set_target_properties(nns_bench2x_custom_pass PROPERTIES OUTPUT_NAME "bench2x_custom_pass")
set_target_properties(nns_bench2x_subplugin_pass PROPERTIES OUTPUT_NAME
                      "nnstreamer_filter_bench2x_pass")
# The sub-plugin resolves nnstreamer_filter_probe() in the benchmark program.
set_target_properties(${name} PROPERTIES ENABLE_EXPORTS ON)
