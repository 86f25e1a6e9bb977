# SPDX-License-Identifier: LGPL-2.1-only
# bench/pytorch_pipeline_bench: LeNet through libtorch, the pytorch back end, and a pipeline.
if(TARGET nns_filter_pytorch)
  find_package(Torch QUIET CONFIG PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/Torch)
  pkg_check_modules(NNS_BENCH_GSTAPP IMPORTED_TARGET gstreamer-app-1.0)
  if(Torch_FOUND AND NNS_BENCH_GSTAPP_FOUND)
    add_executable(pytorch_pipeline_bench ${CMAKE_CURRENT_SOURCE_DIR}/pytorch_pipeline_bench.cc)
    target_include_directories(pytorch_pipeline_bench PRIVATE ${CMAKE_SOURCE_DIR}/tests)
    target_compile_definitions(pytorch_pipeline_bench PRIVATE
      NNS_SOURCE_DIR="${CMAKE_SOURCE_DIR}" NNS_BUILD_DIR="${CMAKE_BINARY_DIR}")
    target_link_libraries(pytorch_pipeline_bench PRIVATE nns_gst PkgConfig::NNS_BENCH_GSTAPP
                          ${TORCH_LIBRARIES} nns_warnings)
    separate_arguments(_nns_torch_flags UNIX_COMMAND "${TORCH_CXX_FLAGS}")
    target_compile_options(pytorch_pipeline_bench PRIVATE ${_nns_torch_flags})
    add_dependencies(pytorch_pipeline_bench nns_filter_pytorch)
  endif()
endif()
