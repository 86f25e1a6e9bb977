# SPDX-License-Identifier: LGPL-2.1-only
# tensor_converter custom-script test: the first input byte selects what convert returns.
#   1 int32 [0,1,2,3]               2 the same, reversed through a negative-stride view
#   3 raises ValueError              4 bytes instead of a numpy array
#   5 an array of 8 bytes for 16     6 two shapes for one array
#   7 a list instead of a tuple      8 rate_n "ten"
#   9 tensors_info holds an int      10 a kept module array, returned on every call
#   11 a slice of the input (bytes 4..11) as 2 int32, i.e. a view inside the input
#   12 an int32 array as a uint8 tensor of the same byte size, numpy integers as rate
import numpy as np
import nnstreamer_python as nns

KEPT = np.arange(10, 14, dtype=np.int32)


class CustomConverter:
    def convert(self, input_array):
        mode = int(input_array[0][0])
        int32x4 = [nns.TensorShape([4], np.int32)]
        seq = np.arange(8, dtype=np.int32)
        if mode == 1:
            return int32x4, [seq[:4].copy()], 10, 1
        if mode == 2:
            return int32x4, [seq[3::-1]], 10, 1
        if mode == 3:
            raise ValueError("mode 3 raises")
        if mode == 4:
            return int32x4, [seq[:4].tobytes()], 10, 1
        if mode == 5:
            return int32x4, [seq[:2].copy()], 10, 1
        if mode == 6:
            return int32x4 * 2, [seq[:4].copy()], 10, 1
        if mode == 7:
            return [int32x4, [seq[:4].copy()], 10, 1]
        if mode == 8:
            return int32x4, [seq[:4].copy()], "ten", 1
        if mode == 9:
            return [7], [seq[:4].copy()], 10, 1
        if mode == 10:
            return int32x4, [KEPT], 10, 1
        if mode == 11:
            return [nns.TensorShape([2], np.int32)], [input_array[0][4:12]], 10, 1
        if mode == 12:
            return [nns.TensorShape([16], np.uint8)], [seq[4:8].copy()], np.int32(10), np.int64(1)
        raise KeyError("no case %d" % mode)
