# SPDX-License-Identifier: LGPL-2.1-only
# Data for the flow-control element tests: the GRU cell recurrence (weights, inputs and the
# step-by-step torch reference) generated at build time with Debian's python3-torch. Without
# torch the test that needs it skips.
set(NNS_FLOW_DATA_DIR ${CMAKE_BINARY_DIR}/tests/data/flow)
execute_process(COMMAND /usr/bin/python3 -c "import torch, numpy"
                RESULT_VARIABLE _flow_torch OUTPUT_QUIET ERROR_QUIET)
if(_flow_torch EQUAL 0)
  add_custom_command(
    OUTPUT ${NNS_FLOW_DATA_DIR}/gru_cell.bin
    COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/data/flow/gru_cell.py ${NNS_FLOW_DATA_DIR}
    DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/data/flow/gru_cell.py
    COMMENT "Generating the GRU cell recurrence data (torch)")
  add_custom_target(nns_flow_gru_data DEPENDS ${NNS_FLOW_DATA_DIR}/gru_cell.bin)
  if(TARGET tensor_repo_gru_test)
    add_dependencies(tensor_repo_gru_test nns_flow_gru_data)
  endif()
else()
  message(STATUS "flow tests: /usr/bin/python3 has no torch; the GRU recurrence test will skip")
endif()
if(TARGET tensor_repo_gru_test)
  target_compile_definitions(tensor_repo_gru_test PRIVATE NNS_FLOW_DATA_DIR="${NNS_FLOW_DATA_DIR}")
endif()
