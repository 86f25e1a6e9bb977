# SPDX-License-Identifier: LGPL-2.1-only
# Single-shot API tests: linked only against libnnstreamer-single, as applications are.
add_executable(ml_single_api api/ml_single_api.cc api/ml_single_dynamic.cc
                             api/ml_single_props.cc)
target_include_directories(ml_single_api PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
target_compile_definitions(ml_single_api PRIVATE NNS_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
                           NNS_BUILD_DIR="${CMAKE_BINARY_DIR}")
target_link_libraries(ml_single_api PRIVATE nnstreamer-single GTest::gtest_main nns_warnings)
# One variable only: gtest_discover_tests splits a ';'-list ENVIRONMENT into separate
# arguments. The build tree's nnstreamer.ini already names the build-tree filter folder.
gtest_discover_tests(ml_single_api DISCOVERY_TIMEOUT 60 PROPERTIES LABELS api TIMEOUT 120
  ENVIRONMENT "NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini")

add_executable(ml_single_c api/ml_single_c.c)
target_link_libraries(ml_single_c PRIVATE nnstreamer-single nns_warnings)
target_compile_definitions(ml_single_c PRIVATE NNS_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
                           NNS_BUILD_DIR="${CMAKE_BINARY_DIR}")
add_test(NAME MlSingleC.CustomEasyFromC COMMAND ml_single_c)
set_tests_properties(MlSingleC.CustomEasyFromC PROPERTIES LABELS api TIMEOUT 120
  ENVIRONMENT "NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;NNSTREAMER_FILTERS=${NNS_BUILD_FILTERS_DIR}")
