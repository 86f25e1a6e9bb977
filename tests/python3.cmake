# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter back end: tests beyond the gtest executables (which skip when it is not built).
if(NOT TARGET nns_filter_python3)
  return()
endif()

# The back end inside a host program that is itself Python (interpreter already initialized).
# PYTHONPATH is cleared: the back end must find nnstreamer_python on its own. Not with sanitizers:
# an ASan-built .so cannot be loaded into an uninstrumented python3.
if(NOT NNS_SANITIZE)
add_test(NAME filter_python3_python_host
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/backends/python3_host_test.py
          $<TARGET_FILE:nns_filter_python3> ${CMAKE_CURRENT_SOURCE_DIR}/data/python
          ${NNS_PYTHON_VERSION_MM})
set_tests_properties(filter_python3_python_host PROPERTIES LABELS backends TIMEOUT 120
  ENVIRONMENT_MODIFICATION "PYTHONPATH=unset:")

# A Python host of another version (here: a pyenv build, when there is one) gets an error from
# open instead of calls into a mismatched interpreter.
file(GLOB _nns_pyenv_pythons "$ENV{HOME}/.pyenv/versions/3.*/bin/python3")
foreach(_py ${_nns_pyenv_pythons})
  if(NOT _py MATCHES "/${NNS_PYTHON_VERSION_MM}[./]")
    add_test(NAME filter_python3_other_python_version
      COMMAND ${_py} ${CMAKE_CURRENT_SOURCE_DIR}/backends/python3_host_test.py
              $<TARGET_FILE:nns_filter_python3> ${CMAKE_CURRENT_SOURCE_DIR}/data/python
              ${NNS_PYTHON_VERSION_MM})
    set_tests_properties(filter_python3_other_python_version PROPERTIES LABELS backends
      TIMEOUT 120 ENVIRONMENT_MODIFICATION "PYTHONPATH=unset:")
    break()
  endif()
endforeach()

# tensor_filter framework=python3 in a PyGObject application (skipped, 77, without PyGObject or
# without the tensor_filter element).
add_test(NAME filter_python3_gi_host
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/backends/python3_gi_host_test.py
          ${CMAKE_CURRENT_SOURCE_DIR}/data/python)
set_tests_properties(filter_python3_gi_host PROPERTIES LABELS backends TIMEOUT 120
  SKIP_RETURN_CODE 77
  ENVIRONMENT "GST_PLUGIN_PATH=${CMAKE_BINARY_DIR}/plugin;GST_REGISTRY=${CMAKE_CURRENT_BINARY_DIR}/python3_gi_registry.bin;NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;NNSTREAMER_FILTERS=${NNS_BUILD_FILTERS_DIR}"
  ENVIRONMENT_MODIFICATION "PYTHONPATH=unset:")
endif()

# A different python3 first on PATH (as pyenv's is here) must not change which standard library
# and site-packages the embedded interpreter uses. The fake one has a stdlib landmark and nothing
# else, so initializing from it would fail.
set(_fake ${CMAKE_CURRENT_BINARY_DIR}/fake_python_prefix)
file(MAKE_DIRECTORY ${_fake}/bin ${_fake}/lib/python${NNS_PYTHON_VERSION_MM})
file(WRITE ${_fake}/lib/python${NNS_PYTHON_VERSION_MM}/os.py "")
file(WRITE ${_fake}/python3.in "#!/bin/sh\nexit 1\n")
file(COPY ${_fake}/python3.in DESTINATION ${_fake}/bin FILE_PERMISSIONS OWNER_READ OWNER_WRITE
     OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
file(RENAME ${_fake}/bin/python3.in ${_fake}/bin/python3)
add_test(NAME filter_python3_foreign_python_on_path
  COMMAND filter_python3_test --gtest_filter=FilterPython3.PassthroughGetDims)
set_tests_properties(filter_python3_foreign_python_on_path PROPERTIES LABELS backends TIMEOUT 120
  ENVIRONMENT "NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;PYTHONPATH=${CMAKE_BINARY_DIR}/python"
  ENVIRONMENT_MODIFICATION "PATH=path_list_prepend:${_fake}/bin")
