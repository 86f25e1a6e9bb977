# SPDX-License-Identifier: LGPL-2.1-only
"""Python side of NNStreamer's python3 sub-plugins (filter, converter, decoder).

Scripts written for NNStreamer import this module and describe tensors with TensorShape:

    import numpy as np
    import nnstreamer_python as nns
    shape = nns.TensorShape([3, 224, 224, 1], np.uint8)

Dimensions are in NNStreamer order, innermost first ("3:224:224:1" is channel, width, height,
batch), i.e. the reverse of the numpy shape of the same data.
"""

import numpy as _np

__all__ = ["TensorShape", "RANK_LIMIT", "SIZE_LIMIT"]

RANK_LIMIT = 16  # NNS_TENSOR_RANK_LIMIT
SIZE_LIMIT = 256  # NNS_TENSOR_SIZE_LIMIT


class TensorShape:
    """Dimensions (innermost first) and numpy element type of one tensor.

    getDims() returns the stored list itself, so a script may edit it in place
    (dims = shape.getDims(); dims[1] = 320) as NNStreamer's own module allows. The list given to
    the constructor or setDims() is copied: a shape built from another shape's getDims() and then
    edited leaves the other shape alone (NNStreamer's module copies the rank-16 lists it hands
    out the same way).
    """

    __slots__ = ("dims", "type")

    def __init__(self, dims=None, type=None):  # noqa: A002 (NNStreamer's keyword names)
        self.dims = []
        self.type = _np.dtype(_np.uint8)
        if dims is not None:
            self.setDims(dims)
        if type is not None:
            try:
                self.type = _np.dtype(type)
            except TypeError as e:
                raise TypeError("TensorShape: %r is not a numpy element type" % (type,)) from e

    def setDims(self, dims):
        """Sets the dimensions (a list of ints, innermost first; the list is copied)."""
        dims = list(dims)  # a copy: the caller's list stays the caller's
        if len(dims) > RANK_LIMIT:
            raise ValueError("TensorShape: rank %d exceeds the limit %d" % (len(dims), RANK_LIMIT))
        self.dims = dims

    def getDims(self):
        """The dimension list, innermost first (the same list object, not a copy)."""
        return self.dims

    def getType(self):
        """The numpy dtype of the elements."""
        return self.type

    def __eq__(self, other):
        if not isinstance(other, TensorShape):
            return NotImplemented
        return list(self.dims) == list(other.dims) and self.type == other.type

    __hash__ = None

    def __repr__(self):
        return "TensorShape(%r, %s)" % (list(self.dims), self.type.name)
