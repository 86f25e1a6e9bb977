# SPDX-License-Identifier: LGPL-2.1-only
# The extension module of `pip install .` (metadata: pyproject.toml). The library comes from
# NNS_LIB_DIR (default <NNS_BUILD_DIR or ../build>/lib), public headers from NNS_INCLUDE_DIR
# (default ../include/nnstreamer); the library's internal header from ../src.
import glob
import os

from pybind11.setup_helpers import Pybind11Extension, build_ext
from setuptools import setup

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
build_dir = os.environ.get("NNS_BUILD_DIR", os.path.join(ROOT, "build"))
lib_dir = os.environ.get("NNS_LIB_DIR", os.path.join(build_dir, "lib"))
include_dir = os.environ.get("NNS_INCLUDE_DIR", os.path.join(ROOT, "include", "nnstreamer"))

ext = Pybind11Extension(
    "nnstreamer._nnstreamer",
    sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "src", "*.cc"))),
    include_dirs=[os.path.join(HERE, "src"), include_dir, os.path.join(ROOT, "src")],
    library_dirs=[lib_dir],
    runtime_library_dirs=[lib_dir],
    libraries=["capi-nnstreamer", "nnstreamer-single"],
    cxx_std=20,
)

setup(ext_modules=[ext], cmdclass={"build_ext": build_ext})
