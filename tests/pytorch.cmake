# SPDX-License-Identifier: LGPL-2.1-only
# pytorch back-end tests: tiny TorchScript models made at build time by a libtorch program, and
# the back-end test depends on the sub-plugin being built.
if(TARGET nns_filter_pytorch)
  find_package(Torch QUIET CONFIG PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/Torch)
  set(NNS_PYTORCH_TEST_MODELS ${CMAKE_BINARY_DIR}/tests/models/pytorch)
  add_executable(pytorch_make_models ${CMAKE_CURRENT_SOURCE_DIR}/backends/pytorch_make_models.cc)
  target_link_libraries(pytorch_make_models PRIVATE ${TORCH_LIBRARIES} nns_warnings)
  separate_arguments(_nns_torch_flags UNIX_COMMAND "${TORCH_CXX_FLAGS}")
  target_compile_options(pytorch_make_models PRIVATE ${_nns_torch_flags})
  add_custom_command(
    OUTPUT ${NNS_PYTORCH_TEST_MODELS}/inplace_add1.pt
    COMMAND ${CMAKE_COMMAND} -E make_directory ${NNS_PYTORCH_TEST_MODELS}
    COMMAND pytorch_make_models ${NNS_PYTORCH_TEST_MODELS}
    DEPENDS pytorch_make_models
    COMMENT "Writing the pytorch test models")
  add_custom_target(pytorch_test_models ALL DEPENDS ${NNS_PYTORCH_TEST_MODELS}/inplace_add1.pt)
  if(TARGET pytorch_backend_test)
    add_dependencies(pytorch_backend_test nns_filter_pytorch pytorch_test_models)
  endif()
  if(TARGET pytorch_filter_test)
    add_dependencies(pytorch_filter_test nns_filter_pytorch)
  endif()
endif()
