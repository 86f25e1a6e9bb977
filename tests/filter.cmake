# SPDX-License-Identifier: LGPL-2.1-only
# Test-only filter back ends and custom filters for tests/elements/tensor_filter*_test.cc.
# They go to build/tests/filter/ (never installed, never in the real sub-plugin folder).
set(NNS_TEST_FILTER_DIR ${CMAKE_BINARY_DIR}/tests/filter)
set(_d ${CMAKE_CURRENT_SOURCE_DIR}/data/filter)
set(_targets)
foreach(n custom_passthrough custom_scaler custom_nosym custom_async)
  add_library(nns_test_${n} MODULE ${_d}/${n}.c)
  set_target_properties(nns_test_${n} PROPERTIES PREFIX "lib" OUTPUT_NAME "${n}"
                        LIBRARY_OUTPUT_DIRECTORY ${NNS_TEST_FILTER_DIR})
  target_include_directories(nns_test_${n} PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
  target_link_libraries(nns_test_${n} PRIVATE nns_warnings)
  list(APPEND _targets nns_test_${n})
endforeach()
add_library(nns_test_backend_testecho MODULE ${_d}/backend_testecho.cc)
add_library(nns_test_backend_badversion MODULE ${_d}/backend_badversion.c)
foreach(n testecho badversion)
  set_target_properties(nns_test_backend_${n} PROPERTIES PREFIX "lib"
                        OUTPUT_NAME "nnstreamer_filter_${n}"
                        LIBRARY_OUTPUT_DIRECTORY ${NNS_TEST_FILTER_DIR})
  target_include_directories(nns_test_backend_${n} PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
  target_link_libraries(nns_test_backend_${n} PRIVATE nns_warnings)
  list(APPEND _targets nns_test_backend_${n})
endforeach()
# A C++ filter library for framework=cpp model=<name>,<lib>; its symbols come from the test
# executable (ENABLE_EXPORTS below), as they come from libnnstreamer.so in a real pipeline.
add_library(nns_test_cpp_filter_lib MODULE ${_d}/cpp_filter_lib.cc)
set_target_properties(nns_test_cpp_filter_lib PROPERTIES PREFIX "lib" OUTPUT_NAME "cpp_filter_lib"
                      LIBRARY_OUTPUT_DIRECTORY ${NNS_TEST_FILTER_DIR})
target_include_directories(nns_test_cpp_filter_lib PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
target_link_libraries(nns_test_cpp_filter_lib PRIVATE nns_warnings)
list(APPEND _targets nns_test_cpp_filter_lib)
# A file with the right name but no entry point.
add_library(nns_test_backend_noentry MODULE ${_d}/custom_nosym.c)
set_target_properties(nns_test_backend_noentry PROPERTIES PREFIX "lib"
                      OUTPUT_NAME "nnstreamer_filter_noentry"
                      LIBRARY_OUTPUT_DIRECTORY ${NNS_TEST_FILTER_DIR})
target_link_libraries(nns_test_backend_noentry PRIVATE nns_warnings)
list(APPEND _targets nns_test_backend_noentry)

file(GLOB _filter_tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/elements/tensor_filter*_test.cc)
foreach(t ${_filter_tests})
  get_filename_component(name ${t} NAME_WE)
  if(TARGET ${name})
    add_dependencies(${name} ${_targets})
    target_compile_definitions(${name} PRIVATE NNS_TEST_FILTER_DIR="${NNS_TEST_FILTER_DIR}")
    set_target_properties(${name} PROPERTIES ENABLE_EXPORTS ON)
  endif()
endforeach()
# These run the generated models through the real back ends.
foreach(t tensor_filter_onnx_test tensor_filter_chain_test filter_reload_leak_test)
  if(TARGET ${t})
    add_dependencies(${t} nns_test_models)
    foreach(b nns_filter_onnxruntime nns_filter_opencv nns_filter_pytorch nns_filter_python3)
      if(TARGET ${b})
        add_dependencies(${t} ${b})
      endif()
    endforeach()
  endif()
endforeach()
