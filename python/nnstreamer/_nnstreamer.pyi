# SPDX-License-Identifier: LGPL-2.1-only
# Type hints of the extension module nnstreamer._nnstreamer.
from typing import Any, Iterable, List, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

ERROR_NONE: int
ERROR_INVALID_PARAMETER: int
ERROR_STREAMS_PIPE: int
ERROR_TRY_AGAIN: int
ERROR_UNKNOWN: int
ERROR_TIMED_OUT: int
ERROR_NOT_SUPPORTED: int
ERROR_PERMISSION_DENIED: int
ERROR_OUT_OF_MEMORY: int
ERROR_IO_ERROR: int
ml_api_version: str

class Error(RuntimeError):
    code: int

class TensorInfo(NamedTuple):
    dtype: np.dtype
    shape: Tuple[int, ...]
    name: Optional[str] = None

TensorSpec = Union[TensorInfo, Tuple[npt.DTypeLike, Sequence[int]],
                   Tuple[npt.DTypeLike, Sequence[int], Optional[str]]]

class Single:
    def __init__(self, model: Union[str, Sequence[str]], framework: Optional[str] = None,
                 **options: Any) -> None: ...
    def invoke(self, *arrays: npt.ArrayLike) -> List[np.ndarray]: ...
    @property
    def input_info(self) -> List[TensorInfo]: ...
    @property
    def output_info(self) -> List[TensorInfo]: ...
    def set_input_info(self, info: Iterable[TensorSpec]) -> None: ...
    def set_timeout(self, ms: int) -> None: ...
    def set_property(self, name: str, value: str) -> None: ...
    def get_property(self, name: str) -> str: ...
    def close(self) -> None: ...
    def __enter__(self) -> "Single": ...
    def __exit__(self, *exc: Any) -> bool: ...
