# SPDX-License-Identifier: LGPL-2.1-only
# tensor_converter custom-script test: the input bytes as int32 tensors without a copy.
# Every input memory becomes one int32 tensor of len/4 elements (a float dimension, as
# NNStreamer's own examples write it); the arrays returned are the input views themselves.
# rate_d 0 keeps the input framerate.
import numpy as np
import nnstreamer_python as nns


class CustomConverter(object):
    def convert(self, input_array):
        tensors_info = [nns.TensorShape([len(a) / 4, 1, 1, 1], np.int32) for a in input_array]
        return tensors_info, input_array, 0, 0
