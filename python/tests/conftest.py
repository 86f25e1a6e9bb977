# SPDX-License-Identifier: LGPL-2.1-only
# Shared fixtures: the build tree (NNS_BUILD_DIR, set by ctest) and its test probe filter.
import os
import pathlib

import pytest

BUILD = pathlib.Path(os.environ.get("NNS_BUILD_DIR", pathlib.Path(__file__).parents[2] / "build"))
SOURCE = pathlib.Path(__file__).parents[2]


def ci() -> bool:
    """In CI (CI=true) nothing may be skipped for a missing model or back end."""
    return os.environ.get("CI") == "true"


def require(condition: bool, why: str) -> None:
    if condition:
        return
    if ci():
        pytest.fail(f"{why} (CI=true: not skipped)")
    pytest.skip(why)


@pytest.fixture(scope="session")
def probe() -> str:
    path = BUILD / "python-api" / "libnns_py_probe.so"
    assert path.is_file(), f"{path} not built (target nns_py_probe)"
    return str(path)


@pytest.fixture(scope="session")
def shared_models() -> pathlib.Path:
    root = pathlib.Path(os.environ.get("NNS_SHARED_DIR", SOURCE.parent / "shared"))
    return root / "models" / "upstream"


def backend_built(name: str) -> bool:
    return (BUILD / "subplugins" / "filters" / f"libnnstreamer_filter_{name}.so").is_file()
