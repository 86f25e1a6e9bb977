# SPDX-License-Identifier: LGPL-2.1-only
# Converter sub-plugins loaded by tensor_converter_test from build/tests/converters (not
# installed): one announcing itself through the entry point, one through a constructor.
set(NNS_TEST_CONVERTERS_DIR ${CMAKE_BINARY_DIR}/tests/converters)
foreach(style entry ctor)
  set(t nns_test_converter_${style})
  add_library(${t} MODULE ${CMAKE_CURRENT_SOURCE_DIR}/elements/test_converter_subplugin.c)
  set_target_properties(${t} PROPERTIES OUTPUT_NAME nnstreamer_converter_test${style} PREFIX lib
                        LIBRARY_OUTPUT_DIRECTORY ${NNS_TEST_CONVERTERS_DIR})
  target_compile_definitions(${t} PRIVATE NNS_TEST_CONVERTER_NAME="test${style}")
  if(style STREQUAL "ctor")
    target_compile_definitions(${t} PRIVATE NNS_TEST_USE_CTOR=1)
  endif()
  target_include_directories(${t} PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
  target_link_libraries(${t} PRIVATE PkgConfig::GST nns_warnings)
endforeach()
if(TARGET tensor_converter_test)
  # The constructor-style sub-plugin resolves registerExternalConverter in the test program.
  set_target_properties(tensor_converter_test PROPERTIES ENABLE_EXPORTS ON)
  add_dependencies(tensor_converter_test nns_test_converter_entry nns_test_converter_ctor)
  target_compile_definitions(tensor_converter_test PRIVATE
                             NNS_TEST_CONVERTERS_DIR="${NNS_TEST_CONVERTERS_DIR}")
endif()
