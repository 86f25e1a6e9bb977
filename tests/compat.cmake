# SPDX-License-Identifier: LGPL-2.1-only
# NNStreamer 2.x utility ABI (src/compat, docs/compat-nnstreamer-2x.md).
set(_c ${CMAKE_CURRENT_SOURCE_DIR}/compat)
set(NNS_COMPAT_TEST_DIR ${CMAKE_BINARY_DIR}/tests/compat)

# compat_util_test (picked up by tests/CMakeLists.txt): the util functions come from the real
# libnnstreamer-single.so, the GStreamer-side ones from the plugin's compat objects.
if(TARGET compat_util_test)
  target_link_libraries(compat_util_test PRIVATE nnstreamer-single nns_compat_gst
                        nnstreamer-decoder-util nnstreamer-converter-util)
  target_include_directories(compat_util_test PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer
                             ${CMAKE_SOURCE_DIR}/backends)
endif()

# compat_more_api_test: the further 2.7 symbols (orc helpers, tensor_data, watchdog, sub-plugin
# table, tensor_common, sparse), from the real libnnstreamer-single.so and the plugin's objects.
if(TARGET compat_more_api_test)
  target_link_libraries(compat_more_api_test PRIVATE nnstreamer-single nns_compat_gst)
  target_include_directories(compat_more_api_test PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
  target_compile_definitions(compat_more_api_test PRIVATE
                             NNS_TEST_FILTER_DIR="${CMAKE_BINARY_DIR}/tests/filter")
  add_dependencies(compat_more_api_test nns_test_custom_passthrough nns_test_custom_scaler)
endif()

# 1. Install the tree into a fresh prefix and build C extensions from it alone (fixture).
set(_program yes)
if(NNS_SANITIZE)
  set(_program no-program)
endif()
add_test(NAME compat.build_extensions
  COMMAND sh ${_c}/build_ext.sh ${CMAKE_BINARY_DIR} ${_c}/ext ${NNS_COMPAT_TEST_DIR}/installed
          ${_program})
set_tests_properties(compat.build_extensions PROPERTIES LABELS compat TIMEOUT 300
  FIXTURES_SETUP compat_ext RESOURCE_LOCK compat_install)

# 2. Every function of the installed headers is exported by the right library, and every
# function of NNStreamer 2.x's nnstreamer_plugin_api_filter.h (the list below, from upstream's
# header) by both libraries, as NNStreamer's tensor_filter_common.c is in both.
set(_upstream_filter_api "nnstreamer_filter_probe,nnstreamer_filter_exit,nnstreamer_filter_find,\
nnstreamer_filter_set_custom_property_desc,get_accl_hw_type,get_accl_hw_str,parse_accl_hw_fill,\
nnstreamer_filter_shared_model_get,nnstreamer_filter_shared_model_insert_and_get,\
nnstreamer_filter_shared_model_remove,nnstreamer_filter_shared_model_replace,\
nnstreamer_filter_dispatch_output_async")
add_test(NAME compat.exports
  COMMAND /usr/bin/python3 ${_c}/check_exports.py
          ${NNS_COMPAT_TEST_DIR}/installed/prefix/${CMAKE_INSTALL_INCLUDEDIR}/nnstreamer
          ${NNS_COMPAT_TEST_DIR}/installed/prefix/${CMAKE_INSTALL_LIBDIR}/libnnstreamer-single.so
          ${NNS_COMPAT_TEST_DIR}/installed/prefix/${CMAKE_INSTALL_LIBDIR}/libnnstreamer.so
          "${NNS_COMPAT_TEST_DIR}/installed/prefix/${CMAKE_INSTALL_LIBDIR}/libnnstreamer-decoder-util.so=loadImageLabels,initSingleLineSprite,_free_labels,setFramerateFromConfig"
          "${NNS_COMPAT_TEST_DIR}/installed/prefix/${CMAKE_INSTALL_LIBDIR}/libnnstreamer-converter-util.so=tcu_get_out_config"
          "${NNS_COMPAT_TEST_DIR}/installed/prefix/${CMAKE_INSTALL_LIBDIR}/libnnstreamer-single.so=${_upstream_filter_api}"
          "${NNS_COMPAT_TEST_DIR}/installed/prefix/${CMAKE_INSTALL_LIBDIR}/libnnstreamer.so=${_upstream_filter_api}")
set_tests_properties(compat.exports PROPERTIES LABELS compat TIMEOUT 60
  FIXTURES_REQUIRED compat_ext)

# 3. The caps/buffer program built against the installed nnstreamer.pc (-lnnstreamer).
if(NOT NNS_SANITIZE)
  add_test(NAME compat.plugin_api_program COMMAND ${NNS_COMPAT_TEST_DIR}/installed/ext/caps_main)
  set_tests_properties(compat.plugin_api_program PROPERTIES LABELS compat TIMEOUT 60
    FIXTURES_REQUIRED compat_ext PASS_REGULAR_EXPRESSION "\nOK\n$")
endif()

# 4. The extensions in pipelines.
add_executable(compat_ext_pipelines ${_c}/ext_pipelines.cc)
target_link_libraries(compat_ext_pipelines PRIVATE nns_test_support nns_warnings)
target_compile_definitions(compat_ext_pipelines PRIVATE
  NNS_COMPAT_EXT_DIR="${NNS_COMPAT_TEST_DIR}/installed/ext")
gtest_discover_tests(compat_ext_pipelines DISCOVERY_TIMEOUT 60
  PROPERTIES LABELS compat TIMEOUT 120 ENVIRONMENT "GST_PLUGIN_PATH=" FIXTURES_REQUIRED compat_ext)

# 5. Symbol binding: a fake NNStreamer library loaded first cannot take our plugin's calls.
add_library(nns_test_bind_fake MODULE ${_c}/bind/fake_nnstreamer.c)
add_library(nns_test_bind_control MODULE ${_c}/bind/control.c)
foreach(t nns_test_bind_fake nns_test_bind_control)
  set_target_properties(${t} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${NNS_COMPAT_TEST_DIR})
  target_link_libraries(${t} PRIVATE nns_warnings)
endforeach()
add_executable(compat_bind_check ${_c}/bind_check.cc)
target_include_directories(compat_bind_check PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
target_link_libraries(compat_bind_check PRIVATE PkgConfig::GST PkgConfig::GSTCHECK GTest::gtest_main
                      ${CMAKE_DL_LIBS} nns_warnings)
target_compile_definitions(compat_bind_check PRIVATE
  NNS_BIND_FAKE_LIB="$<TARGET_FILE:nns_test_bind_fake>"
  NNS_BIND_CONTROL_LIB="$<TARGET_FILE:nns_test_bind_control>"
  NNS_BIND_PLUGIN="$<TARGET_FILE:nnstreamer>")
add_dependencies(compat_bind_check nnstreamer nns_test_bind_fake nns_test_bind_control)
gtest_discover_tests(compat_bind_check DISCOVERY_TIMEOUT 60
  PROPERTIES LABELS compat TIMEOUT 120 ENVIRONMENT "GST_PLUGIN_PATH=")

# 6. nnstreamer_filter_find() for each of our back ends, from a C program written as 2.x code
# (NNStreamer's headers, linked to libnnstreamer.so): real models opened, invoked, compared.
add_executable(compat_find_frameworks ${_c}/find_frameworks.c)
target_include_directories(compat_find_frameworks PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
target_link_libraries(compat_find_frameworks PRIVATE ${CMAKE_BINARY_DIR}/lib/libnnstreamer.so
                      PkgConfig::GST nns_warnings)
set_target_properties(compat_find_frameworks PROPERTIES BUILD_RPATH ${CMAKE_BINARY_DIR}/lib)
add_dependencies(compat_find_frameworks nnstreamer nns_test_custom_scaler)
if(NOT NNS_SANITIZE)  # the program loads the plugin itself
  set(_shared ${CMAKE_SOURCE_DIR}/../shared/models/upstream)
  if(DEFINED ENV{NNS_SHARED_DIR})
    set(_shared $ENV{NNS_SHARED_DIR}/models/upstream)
  endif()
  add_test(NAME compat.find_frameworks
    COMMAND compat_find_frameworks ${_shared} ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR}/tests/filter)
  set_tests_properties(compat.find_frameworks PROPERTIES LABELS compat TIMEOUT 120
    PASS_REGULAR_EXPRESSION "\nOK\n$"
    ENVIRONMENT "GST_PLUGIN_PATH=;NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;\
NNSTREAMER_FILTERS=${CMAKE_BINARY_DIR}/subplugins/filters;\
NNSTREAMER_DECODERS=${CMAKE_BINARY_DIR}/subplugins/decoders;\
NNSTREAMER_CONVERTERS=${CMAKE_BINARY_DIR}/subplugins/converters;\
PYTHONPATH=${CMAKE_BINARY_DIR}/python")
endif()
