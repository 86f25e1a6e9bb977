# SPDX-License-Identifier: LGPL-2.1-only
# The speech detection demo (examples/vad) as a test: synthesized speech padded with silence must
# give segments where the speech is, and feeding the state back must beat a stateless run
# (tests/vad/vad_test.sh). Exit 77 (model, ONNX Runtime back end or espeak-ng missing) = skipped.
if(NNS_BUILD_EXAMPLES)
  add_test(NAME demo.vad COMMAND bash ${CMAKE_SOURCE_DIR}/tests/vad/vad_test.sh)
  set_tests_properties(demo.vad PROPERTIES
    ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR}"
    SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)
endif()
