# SPDX-License-Identifier: LGPL-2.1-only
# The main demo as a test: exit 77 (an element it needs is not built yet) counts as skipped.
if(NNS_BUILD_EXAMPLES)
  add_test(NAME demo.run_demo COMMAND bash ${CMAKE_SOURCE_DIR}/examples/demo/run_demo.sh)
  set_tests_properties(demo.run_demo PROPERTIES
    ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_FACE_SKIP_MISSING=1"
    SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)
endif()
