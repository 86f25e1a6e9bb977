# SPDX-License-Identifier: LGPL-2.1-only
# The core plugin and the single-shot library never link a heavy framework (libtorch, ONNX
# Runtime, Arm NN, OpenCV, Python): their ELF NEEDED entries are read with readelf -d.
set(_nns_needed_files $<TARGET_FILE:nnstreamer>)
if(TARGET nnstreamer-single)
  list(APPEND _nns_needed_files $<TARGET_FILE:nnstreamer-single>)
endif()
add_test(NAME plugin.no_framework_libraries
  COMMAND ${CMAKE_COMMAND} -DREADELF=${CMAKE_READELF} "-DFILES=${_nns_needed_files}"
          -P ${CMAKE_CURRENT_SOURCE_DIR}/support/check_needed.cmake)
set_tests_properties(plugin.no_framework_libraries PROPERTIES LABELS elements TIMEOUT 30)
