# SPDX-License-Identifier: LGPL-2.1-only
# The paper experiments (examples/paper, docs/paper-experiments.md) in smoke mode: a few frames
# per experiment, pipeline and Control runs must agree on the model outputs (report.py check)
# and the four plots and the tables must be produced. Exit 77 (models, program or ONNX Runtime
# back end missing; NNS_PAPER_SKIP_MISSING=1) counts as skipped, except in CI.
if(NNS_BUILD_EXAMPLES AND TARGET nns_onnxruntime)
  add_test(NAME paper.smoke COMMAND bash ${CMAKE_SOURCE_DIR}/examples/paper/run.sh --smoke)
  set_tests_properties(paper.smoke PROPERTIES
    ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_PAPER_SKIP_MISSING=1"
    PASS_REGULAR_EXPRESSION "paper: done: 10 runs"
    SKIP_RETURN_CODE 77 LABELS paper TIMEOUT 60)
endif()
# report.py check itself: it fails on different, shorter or missing pipeline outputs.
add_test(NAME paper.report_check COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/paper/report_check_test.sh)
set_tests_properties(paper.report_check PROPERTIES LABELS paper TIMEOUT 30
  PASS_REGULAR_EXPRESSION "all cases as expected")
