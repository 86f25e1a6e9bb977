# SPDX-License-Identifier: LGPL-2.1-only
# The among-device demo (examples/among_device/run.sh) as a test: exit 77 (model, photo or ONNX
# Runtime missing, NNS_SKIP_MISSING=1) counts as skipped, except in CI (examples/common.sh nns_ci).
if(NNS_BUILD_EXAMPLES)
  add_test(NAME demo.among_device COMMAND bash ${CMAKE_SOURCE_DIR}/examples/among_device/run.sh)
  set_tests_properties(demo.among_device PROPERTIES
    ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_SKIP_MISSING=1"
    PASS_REGULAR_EXPRESSION "label: orange" SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)
endif()
