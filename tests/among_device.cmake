# SPDX-License-Identifier: LGPL-2.1-only
# The among-device demo (examples/among_device/run.sh) as a test: the orange photo classified by
# a query server over TCP, then over HYBRID (a mosquitto the script starts): both lines must
# print "orange" (NNS_EXPECT_LABEL also makes the script fail otherwise). Exit 77 (shared models,
# photo, ONNX Runtime or mosquitto missing, NNS_SKIP_MISSING=1) counts as skipped, except in CI
# (examples/common.sh nns_ci).
if(NNS_BUILD_EXAMPLES)
  add_test(NAME demo.among_device COMMAND bash ${CMAKE_SOURCE_DIR}/examples/among_device/run.sh)
  set_tests_properties(demo.among_device PROPERTIES
    ENVIRONMENT
      "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_SHARED_DIR=${NNS_SHARED_DIR};NNS_SKIP_MISSING=1;NNS_EXPECT_LABEL=orange"
    PASS_REGULAR_EXPRESSION "TCP: +label: orange, round trip [0-9]+ us.*HYBRID: +label: orange, round trip [0-9]+ us"
    SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)
endif()
