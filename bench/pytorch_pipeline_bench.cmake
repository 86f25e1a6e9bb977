# SPDX-License-Identifier: LGPL-2.1-only
# pytorch_pipeline_bench also links libtorch (for the plain-libtorch loop) and gstreamer-app, and
# needs the pytorch back end; without libtorch it is left out of the default build.
find_package(Torch QUIET CONFIG PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/Torch)
pkg_check_modules(NNS_BENCH_GSTAPP QUIET IMPORTED_TARGET gstreamer-app-1.0)
if(Torch_FOUND AND NNS_BENCH_GSTAPP_FOUND AND TARGET nns_filter_pytorch)
  target_include_directories(${name} PRIVATE ${CMAKE_SOURCE_DIR}/tests)
  target_compile_definitions(${name} PRIVATE NNS_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
                             NNS_BUILD_DIR="${CMAKE_BINARY_DIR}")
  target_link_libraries(${name} PRIVATE PkgConfig::NNS_BENCH_GSTAPP ${TORCH_LIBRARIES})
  separate_arguments(_nns_torch_flags UNIX_COMMAND "${TORCH_CXX_FLAGS}")
  target_compile_options(${name} PRIVATE ${_nns_torch_flags})
  add_dependencies(${name} nns_filter_pytorch)
else()
  message(STATUS "bench: ${name} not built by default (needs libtorch and the pytorch back end)")
  set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL TRUE)
endif()
