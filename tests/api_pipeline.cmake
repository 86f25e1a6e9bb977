# SPDX-License-Identifier: LGPL-2.1-only
# Pipeline API tests: linked only against libcapi-nnstreamer (and through it
# libnnstreamer-single), as applications are; the nnstreamer plugin is loaded from build/plugin
# (tests/api/ml_pipeline_main.cc sets GST_PLUGIN_PATH), so it must be built first.
add_executable(ml_pipeline_api api/ml_pipeline_main.cc api/ml_pipeline_api.cc
                               api/ml_pipeline_controls.cc api/ml_pipeline_threads.cc)
target_include_directories(ml_pipeline_api PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}
                           ${CMAKE_CURRENT_SOURCE_DIR}/support)
target_compile_definitions(ml_pipeline_api PRIVATE NNS_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
                           NNS_BUILD_DIR="${CMAKE_BINARY_DIR}" NNS_GST_PLUGINS_DIR="${GST_PLUGINS_DIR}")
target_link_libraries(ml_pipeline_api PRIVATE capi-nnstreamer GTest::gtest nns_warnings
                      Threads::Threads PkgConfig::GST)
add_dependencies(ml_pipeline_api nnstreamer)
gtest_discover_tests(ml_pipeline_api DISCOVERY_TIMEOUT 60 PROPERTIES LABELS api TIMEOUT 120)

# The system plugins the tests use, linked into one folder (GST_PLUGIN_SYSTEM_PATH of the tests;
# ml_pipeline_main.cc makes the same links when run by hand from another tree).
set(_capi_sys ${CMAKE_BINARY_DIR}/tests/capi-gst-plugins)
file(MAKE_DIRECTORY ${_capi_sys})
foreach(_p libgstcoreelements.so libgstapp.so libgstvideotestsrc.so libgstaudiotestsrc.so
        libgstvideoconvertscale.so)
  if(EXISTS ${GST_PLUGINS_DIR}/${_p} AND NOT EXISTS ${_capi_sys}/${_p})
    file(CREATE_LINK ${GST_PLUGINS_DIR}/${_p} ${_capi_sys}/${_p} SYMBOLIC)
  endif()
endforeach()

# nnstreamer.h compiled as C: the header is C, and a whole pipeline runs from C.
add_executable(ml_pipeline_c api/ml_pipeline_c.c)
target_link_libraries(ml_pipeline_c PRIVATE capi-nnstreamer nns_warnings PkgConfig::GST)
target_compile_definitions(ml_pipeline_c PRIVATE NNS_BUILD_DIR="${CMAKE_BINARY_DIR}")
# Same environment as tests/api/ml_pipeline_main.cc.
set(_capi_env "GST_PLUGIN_SYSTEM_PATH=${_capi_sys}"
    "GST_PLUGIN_PATH=${CMAKE_BINARY_DIR}/plugin" "GST_REGISTRY_FORK=no"
    "GST_REGISTRY=${CMAKE_BINARY_DIR}/tests/capi-registry-c.bin")
add_dependencies(ml_pipeline_c nnstreamer)
add_test(NAME MlPipelineC.AppsrcCustomEasySink COMMAND ml_pipeline_c)
set_tests_properties(MlPipelineC.AppsrcCustomEasySink PROPERTIES LABELS api TIMEOUT 120
                     ENVIRONMENT "${_capi_env}")
