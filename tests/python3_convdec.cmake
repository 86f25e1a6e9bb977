# SPDX-License-Identifier: LGPL-2.1-only
# python3 converter and decoder sub-plugins inside a PyGObject application (skipped, 77, without
# PyGObject or the elements). Not with sanitizers: an ASan-built .so cannot be loaded into an
# uninstrumented python3.
if(NOT TARGET nns_decoder_python3 OR NOT TARGET nns_converter_python3 OR NNS_SANITIZE)
  return()
endif()
add_test(NAME python3_convdec_gi_host
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/backends/python3_convdec_gi_host_test.py
          ${CMAKE_CURRENT_SOURCE_DIR}/data/python/convdec)
set_tests_properties(python3_convdec_gi_host PROPERTIES LABELS backends TIMEOUT 120
  SKIP_RETURN_CODE 77
  ENVIRONMENT "GST_PLUGIN_PATH=${CMAKE_BINARY_DIR}/plugin;GST_REGISTRY=${CMAKE_CURRENT_BINARY_DIR}/python3_convdec_gi_registry.bin;NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;NNSTREAMER_DECODERS=${CMAKE_BINARY_DIR}/subplugins/decoders;NNSTREAMER_CONVERTERS=${CMAKE_BINARY_DIR}/subplugins/converters"
  ENVIRONMENT_MODIFICATION "PYTHONPATH=unset:")
