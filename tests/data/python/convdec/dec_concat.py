# SPDX-License-Identifier: LGPL-2.1-only
# tensor_decoder python3 test: no getOutCaps (application/octet-stream); the tensors' bytes one
# after the other. The first byte of the first tensor selects another result:
#   201 a bytearray   202 a numpy array   203 an empty frame   (others: bytes)
import numpy as np


class CustomDecoder(object):
    def decode(self, raw_data, in_info, rate_n, rate_d):
        out = b"".join(a.tobytes() for a in raw_data)
        first = raw_data[0].view(np.uint8)[0]
        if first == 201:
            return bytearray(out)
        if first == 202:
            return np.frombuffer(out, dtype=np.uint8).copy()
        if first == 203:
            return b""
        return out
