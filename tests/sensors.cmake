# SPDX-License-Identifier: LGPL-2.1-only
# The multi-sensor demo (examples/sensors/run.sh) as a test: two fake IIO sensors through
# tensor_src_iio, tensor_aggregator and tensor_mux into a GRU on PyTorch; the outputs must equal
# torch's on the same sensor values. Exit 77 (PyTorch back end or python3-torch missing) = skipped,
# except under CI=true.
if(NNS_BUILD_EXAMPLES)
  add_test(NAME demo.sensors_e2 COMMAND bash ${CMAKE_SOURCE_DIR}/examples/sensors/run.sh 5)
  set_tests_properties(demo.sensors_e2 PROPERTIES
    ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_SENSORS_SKIP_MISSING=1"
    SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)
endif()
