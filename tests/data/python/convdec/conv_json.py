# SPDX-License-Identifier: LGPL-2.1-only
# tensor_converter custom-script test: a JSON document -> two tensors.
#   {"name": "<text>", "values": [<int>, ...]}
#   tensor 0: the name as UTF-8 bytes plus a NUL (uint8, dims [len+1, 1, 1, 1])
#   tensor 1: the values (int32, dims [count, 1, 1, 1])
# Framerate 10/1.
import json

import numpy as np
import nnstreamer_python as nns


class CustomConverter(object):
    def convert(self, input_array):
        doc = json.loads(input_array[0].tobytes())
        name = np.frombuffer((doc["name"] + "\0").encode(), dtype=np.uint8)
        values = np.array(doc["values"], dtype=np.int32)
        tensors_info = [
            nns.TensorShape([len(name), 1, 1, 1], np.uint8),
            nns.TensorShape([len(values), 1, 1, 1], np.int32),
        ]
        return tensors_info, [name, values], 10, 1
