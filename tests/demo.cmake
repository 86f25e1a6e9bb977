# SPDX-License-Identifier: LGPL-2.1-only
# The main demo as a test: exit 77 (an element it needs is not built yet, or with
# NNS_FACE_SKIP_MISSING=1 the face model or back end missing) counts as skipped, except in CI
# (CI=true when the test runs), where run_demo.sh fails instead (examples/common.sh nns_ci).
if(NNS_BUILD_EXAMPLES)
  add_test(NAME demo.run_demo COMMAND bash ${CMAKE_SOURCE_DIR}/examples/demo/run_demo.sh)
  set_tests_properties(demo.run_demo PROPERTIES
    ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_FACE_SKIP_MISSING=1"
    SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)
endif()
# run_demo.sh skips locally but fails in CI when something is missing (a fake build tree).
add_test(NAME demo.ci_never_skips COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/support/demo_ci_test.sh)
set_tests_properties(demo.ci_never_skips PROPERTIES LABELS demo TIMEOUT 60)
