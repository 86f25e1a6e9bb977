# SPDX-License-Identifier: LGPL-2.1-only
# tensor_converter custom-script test: the inverse of dec_flexbuf.py (one FlexBuffers map ->
# the tensors it describes, with its framerate).
import numpy as np
import nnstreamer_python as nns
from flatbuffers import flexbuffers

TYPES = [np.int32, np.uint32, np.int16, np.uint16, np.int8, np.uint8,
         np.float64, np.float32, np.int64, np.uint64]


class CustomConverter(object):
    def convert(self, input_array):
        root = flexbuffers.GetRoot(input_array[0].tobytes()).AsMap
        tensors_info = []
        raw_data = []
        for i in range(root["num_tensors"].AsInt):
            tensor = root["tensor_%d" % i].AsVector
            ttype = TYPES[tensor[1].AsInt]
            dims = [d.AsInt for d in tensor[2].AsTypedVector]
            tensors_info.append(nns.TensorShape(dims, ttype))
            raw_data.append(np.frombuffer(tensor[3].AsBlob, dtype=ttype))
        return tensors_info, raw_data, root["rate_n"].AsInt, root["rate_d"].AsInt
