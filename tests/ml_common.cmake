# SPDX-License-Identifier: LGPL-2.1-only
# The common ML API (ml-api-common.h, ml_information_*, version, error codes): linked only
# against libnnstreamer-single, with src/ for the library's internal header.
add_executable(ml_common_api api/ml_common_api.cc)
target_include_directories(ml_common_api PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer
                           ${CMAKE_SOURCE_DIR}/src)
target_compile_definitions(ml_common_api PRIVATE NNS_BUILD_DIR="${CMAKE_BINARY_DIR}")
target_link_libraries(ml_common_api PRIVATE nnstreamer-single GTest::gtest_main nns_warnings)
gtest_discover_tests(ml_common_api DISCOVERY_TIMEOUT 60 PROPERTIES LABELS api TIMEOUT 60
  ENVIRONMENT "NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini")
