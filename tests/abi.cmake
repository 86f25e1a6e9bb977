# SPDX-License-Identifier: LGPL-2.1-only
# The exported dynamic symbols of every library we ship (targets given a cmake/abi/*.map by
# nns_export_map) against the checked-in lists tests/abi/*.symbols
# (docs/abi.md). `cmake --build build --target abi-update` rewrites the lists from the build.
# Not in the sanitizer tree (instrumented libraries, and its set of libraries differs).
if(NOT NNS_SANITIZE)
  get_property(_abi_targets GLOBAL PROPERTY NNS_ABI_TARGETS)
  set(_abi_lines "")
  foreach(t ${_abi_targets})
    # The list is named after the file, but for the Python module, whose file name carries the
    # interpreter's ABI tag.
    set(_name "$<TARGET_FILE_NAME:${t}>")
    if(t STREQUAL "nns_python_api")
      set(_name "python-nnstreamer-module")
    endif()
    string(APPEND _abi_lines "${_name}=$<TARGET_FILE:${t}>\n")
  endforeach()
  file(GENERATE OUTPUT ${CMAKE_BINARY_DIR}/tests/abi-manifest.txt CONTENT "${_abi_lines}")
  set(_abi_cmd /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/abi/check_abi.py
      ${CMAKE_BINARY_DIR}/tests/abi-manifest.txt ${CMAKE_CURRENT_SOURCE_DIR}/abi)
  add_test(NAME abi.symbols COMMAND ${_abi_cmd})
  set_tests_properties(abi.symbols PROPERTIES LABELS "abi;compat" TIMEOUT 60)
  add_custom_target(abi-update COMMAND ${_abi_cmd} --update DEPENDS ${_abi_targets}
    COMMENT "Rewriting tests/abi/*.symbols from the built libraries" VERBATIM)
endif()
