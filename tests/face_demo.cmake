# SPDX-License-Identifier: LGPL-2.1-only
# The face demo as a test: it must print the astronaut's face with a high score near the top
# centre of the photo. Exit 77 (elements not built yet, or with NNS_FACE_SKIP_MISSING=1 the
# model/photo unavailable) counts as skipped.
if(NNS_BUILD_EXAMPLES)
  add_test(NAME demo.face_demo COMMAND bash ${CMAKE_SOURCE_DIR}/examples/face_demo/run.sh)
  set_tests_properties(demo.face_demo PROPERTIES
    ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_FACE_SKIP_MISSING=1;NNS_FACE_OUTPUT=${CMAKE_BINARY_DIR}/demo/faces-test.png"
    PASS_REGULAR_EXPRESSION "1 face\\(s\\).*face 1: score 0\\.9[0-9] box x=1[6-9][0-9] y=[6-9][0-9] w=[89][0-9] h=[89][0-9]"
    SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)
endif()
