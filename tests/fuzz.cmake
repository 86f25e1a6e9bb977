# SPDX-License-Identifier: LGPL-2.1-only
# ctest -L fuzz: builds fuzz/ with clang++ into <build>/fuzz and runs every libFuzzer target
# (scripts/fuzz.sh) for NNS_FUZZ_SECONDS in total (default 180, shared by the targets). Any
# crash, leak, UB or broken property fails the test; the reproducer is kept in
# <build>/fuzz/artifacts/. Without clang++ or the wire dependencies the test is not registered.
find_program(NNS_CLANGXX NAMES clang++ clang++-14)
if(NNS_CLANGXX AND TARGET nns_wire)
  add_test(NAME fuzz_targets COMMAND ${CMAKE_SOURCE_DIR}/scripts/fuzz.sh)
  set_tests_properties(fuzz_targets PROPERTIES LABELS fuzz TIMEOUT 1200
    ENVIRONMENT "NNS_FUZZ_DIR=${CMAKE_BINARY_DIR}/fuzz;CXX=${NNS_CLANGXX};NNS_JOBS=2")
else()
  message(STATUS "fuzz: clang++ or the wire formats missing; ctest fuzz_targets not registered")
endif()
