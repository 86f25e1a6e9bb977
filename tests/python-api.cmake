# SPDX-License-Identifier: LGPL-2.1-only
# The Python package's pytest suite (python/tests) on Debian's /usr/bin/python3, with the
# build tree's package (build/python) and sub-plugins. pytest prints its own summary line.
if(NOT TARGET nns_python_api)
  return()
endif()
add_test(NAME python_api.pytest
  COMMAND /usr/bin/python3 -m pytest -q -p no:cacheprovider -rs ${CMAKE_SOURCE_DIR}/python/tests)
set_tests_properties(python_api.pytest PROPERTIES LABELS python-api TIMEOUT 300
  ENVIRONMENT "PYTHONPATH=${CMAKE_BINARY_DIR}/python;NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;NNSTREAMER_FILTERS=${NNS_BUILD_FILTERS_DIR};PYTHONDONTWRITEBYTECODE=1")
