# SPDX-License-Identifier: LGPL-2.1-only
# The Python package's pytest suite (python/tests) on Debian's /usr/bin/python3, with the
# build tree's package (build/python) and sub-plugins. pytest prints its own summary line.
if(NOT TARGET nns_python_api)
  return()
endif()
# Pipelines load the build tree's plugin, with a registry cache of their own.
set(_nns_py_gst "GST_PLUGIN_PATH=${CMAKE_BINARY_DIR}/plugin;GST_REGISTRY=${CMAKE_BINARY_DIR}/python-api/gst-registry.bin")
set(_nns_py_shared "${CMAKE_SOURCE_DIR}/../shared")  # models (as tests/segpose.cmake)
if(DEFINED ENV{NNS_SHARED_DIR})
  set(_nns_py_shared "$ENV{NNS_SHARED_DIR}")
endif()
add_test(NAME python_api.pytest
  COMMAND /usr/bin/python3 -m pytest -q -p no:cacheprovider -rs ${CMAKE_SOURCE_DIR}/python/tests)
set_tests_properties(python_api.pytest PROPERTIES LABELS python-api TIMEOUT 300
  ENVIRONMENT "PYTHONPATH=${CMAKE_BINARY_DIR}/python;${_nns_py_gst};NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_SHARED_DIR=${_nns_py_shared};NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;NNSTREAMER_FILTERS=${NNS_BUILD_FILTERS_DIR};PYTHONDONTWRITEBYTECODE=1")

# examples/python: the picture classified with nnstreamer.Single prints "orange" (skipped when
# the model is missing, except in CI: the script exits 1 there).
add_test(NAME example.python_classify
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/examples/python/classify_orange.py)
set_tests_properties(example.python_classify PROPERTIES LABELS demo TIMEOUT 60
  PASS_REGULAR_EXPRESSION "^orange\n$" SKIP_RETURN_CODE 77
  ENVIRONMENT "PYTHONPATH=${CMAKE_BINARY_DIR}/python;${_nns_py_gst};NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_SHARED_DIR=${_nns_py_shared};NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;NNS_SKIP_MISSING=1;PYTHONDONTWRITEBYTECODE=1")

# `pip install .` (python/pyproject.toml + setup.py) with Debian's pip/setuptools/pybind11, no
# download (--no-index), into a temporary folder; the installed package then runs a model.
add_test(NAME python_api.pip_install
  COMMAND bash -c "set -e; t=$(mktemp -d); trap 'rm -rf \"$t\"' EXIT; cd \"$0\"; /usr/bin/python3 -m pip install -q --no-build-isolation --no-index --no-deps --target \"$t\" . 2>&1 | grep -v 'Running pip as the' || true; cd \"$t\"; PYTHONPATH=\"$t\" /usr/bin/python3 -c 'import sys, numpy, nnstreamer; print(nnstreamer.__file__); m = nnstreamer.Single(sys.argv[1], \"custom\"); print(m.invoke(numpy.arange(4, dtype=numpy.uint8))[0].tolist())' \"$1\""
          ${CMAKE_SOURCE_DIR}/python ${CMAKE_BINARY_DIR}/python-api/libnns_py_probe.so)
set_tests_properties(python_api.pip_install PROPERTIES LABELS "python-api;slow" TIMEOUT 600
  PASS_REGULAR_EXPRESSION "/nnstreamer/__init__.py\n\\[0, 1, 2, 3\\]"
  ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;PYTHONDONTWRITEBYTECODE=1")

# examples/python/count_frames.py: a Python callback counts the 30 frames of a pipeline.
add_test(NAME example.python_count_frames
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/examples/python/count_frames.py 30)
set_tests_properties(example.python_count_frames PROPERTIES LABELS demo TIMEOUT 60
  PASS_REGULAR_EXPRESSION "^30 frames, tensor \\(1, 48, 64, 3\\) uint8, mean of the last frame"
  ENVIRONMENT "PYTHONPATH=${CMAKE_BINARY_DIR}/python;${_nns_py_gst};NNSTREAMER_CONF=${CMAKE_BINARY_DIR}/nnstreamer.ini;PYTHONDONTWRITEBYTECODE=1")
