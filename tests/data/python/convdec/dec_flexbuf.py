# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: tensors -> one FlexBuffers map (other/flexbuf), laid out as
# NNStreamer's flexbuf decoder does: num_tensors, rate_n, rate_d and, per tensor,
# tensor_<i> = [name, tensor type number, dims (4 ints), data blob].
import numpy as np
import nnstreamer_python as nns  # noqa: F401 (the module scripts import)
from flatbuffers import flexbuffers

# NNStreamer's tensor type numbering.
TYPES = [np.int32, np.uint32, np.int16, np.uint16, np.int8, np.uint8,
         np.float64, np.float32, np.int64, np.uint64]


def tensor_type(dtype):
    for number, t in enumerate(TYPES):
        if dtype == t:
            return number
    raise TypeError("no NNStreamer tensor type for %s" % (dtype,))


class CustomDecoder(object):
    def getOutCaps(self):
        return bytes("other/flexbuf", "UTF-8")

    def decode(self, raw_data, in_info, rate_n, rate_d):
        fbb = flexbuffers.Builder()
        with fbb.Map():
            fbb.UInt("num_tensors", len(in_info))
            fbb.Int("rate_n", rate_n)
            fbb.Int("rate_d", rate_d)
            for i, info in enumerate(in_info):
                with fbb.Vector("tensor_%d" % i):
                    fbb.String("")
                    fbb.Int(tensor_type(info.getType().type))
                    with fbb.TypedVector():
                        for d in info.getDims()[:4]:
                            fbb.Int(d)
                    fbb.Blob(raw_data[i].view(np.uint8))
        return bytes(fbb.Finish())
