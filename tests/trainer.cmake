# SPDX-License-Identifier: LGPL-2.1-only
# tensor_trainer: a C test trainer sub-plugin built against the 2.x trainer ABI
# (tests/trainer/counting_trainer.c -> <build>/tests/trainers/libnnstreamer_trainer_counting.so),
# which tensor_trainer_test loads through NNSTREAMER_TRAINERS; and the digits demo
# (examples/trainer/run.sh) with the PyTorch trainer.
if(TARGET tensor_trainer_test)
  add_library(nns_test_trainer_counting MODULE ${CMAKE_CURRENT_SOURCE_DIR}/trainer/counting_trainer.c)
  target_include_directories(nns_test_trainer_counting PRIVATE ${CMAKE_SOURCE_DIR}/include/nnstreamer)
  target_link_libraries(nns_test_trainer_counting PRIVATE Threads::Threads)
  set_target_properties(nns_test_trainer_counting PROPERTIES
    OUTPUT_NAME nnstreamer_trainer_counting PREFIX lib
    LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests/trainers)
  add_dependencies(tensor_trainer_test nns_test_trainer_counting)
  target_compile_definitions(tensor_trainer_test PRIVATE
    NNS_TEST_TRAINERS_DIR="${CMAKE_BINARY_DIR}/tests/trainers")
  # The sub-plugin calls nnstreamer_trainer_notify_event(), which comes from libnnstreamer.so in
  # a real pipeline and from this executable (static plugin) here.
  set_target_properties(tensor_trainer_test PROPERTIES ENABLE_EXPORTS ON)
endif()
if(NNS_BUILD_EXAMPLES)
  add_test(NAME demo.trainer_digits COMMAND bash ${CMAKE_SOURCE_DIR}/examples/trainer/run.sh 8)
  set_tests_properties(demo.trainer_digits PROPERTIES
    ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_TRAINER_SKIP_MISSING=1"
    SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 180)
endif()
